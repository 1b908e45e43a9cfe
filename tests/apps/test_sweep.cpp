// `clothsim sweep`, end to end (docs/batch.md): a 2 x 2 grid writes four complete run folders and
// an index; two shards of it together write the same four folders; an interrupted sweep run again
// resumes without redoing the runs already complete; the runs equal `clothsim run` with --set;
// bad input stops the sweep before it writes anything.
#include <signal.h>
#include <sys/stat.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.h"
#include "test_checks.h"

namespace clothsim {
namespace {

namespace fs = std::filesystem;
using checks::contains;
using checks::read_text;
using cli_harness::describe;
using cli_harness::wait_clothsim;
using Result = checks::ProcessResult;

const std::vector<std::string> kRunFolders = {"run-0000", "run-0001", "run-0002", "run-0003"};
const std::vector<std::string> kStreamedFiles = {"positions.npy", "velocities.npy", "energy.csv"};

// The 2 x 2 grid, on the paper's Figure 4 sheet (self-collision on), short runs.
std::vector<std::string> grid_args(const std::string& out, const std::string& duration = "0.3") {
  return {"sweep",      "paper-fig4",
          "--param",    "springs.connector.stiffness=40,80",
          "--param",    "output.fps=30,60",
          "--duration", duration,
          "--render",   "none",
          "--out",      out};
}

std::vector<std::vector<std::string>> read_csv(const fs::path& path) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(read_text(path));
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::istringstream fields(line);
    std::string cell;
    while (std::getline(fields, cell, ',')) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

std::string column(const std::vector<std::vector<std::string>>& rows, std::size_t row, const std::string& name) {
  for (std::size_t c = 0; c < rows[0].size(); ++c) {
    if (rows[0][c] == name) return c < rows[row].size() ? rows[row][c] : "";
  }
  ADD_FAILURE() << "index.csv has no column " << name;
  return {};
}

class SweepTest : public cli_harness::ToolTest {
 protected:
  SweepTest() : ToolTest("sweep") {}

  void expect_same_runs(const std::string& a, const std::string& b) const {
    for (const std::string& run : kRunFolders) {
      for (const std::string& file : kStreamedFiles) {
        const std::string left = read_text(work_ / a / run / file);
        ASSERT_FALSE(left.empty()) << a << "/" << run << "/" << file;
        EXPECT_TRUE(left == read_text(work_ / b / run / file)) << run << "/" << file << " differs: " << a << ", " << b;
      }
    }
  }
};

// --report: each run writes its report.html, and the sweep a page of index.csv linking to them.
// The sweep's record does not change with it: the same sweep again without --report goes on.
TEST_F(SweepTest, ReportWritesEachRunsPageAndTheIndexPage) {
  std::vector<std::string> args = grid_args("pages", "0.1");
  args.emplace_back("--report");
  const Result result = clothsim(args);
  ASSERT_EQ(result.exit_code, 0) << describe(result);
  const std::string index = read_text(work_ / "pages" / "report.html");
  for (const std::string& run : kRunFolders) {
    EXPECT_TRUE(fs::exists(work_ / "pages" / run / "report.html")) << run;
    EXPECT_TRUE(contains(index, "<a href=\"" + run + "/report.html\">" + run + "</a>")) << run;
  }
  EXPECT_TRUE(contains(index, "springs.connector.stiffness"));
  const Result again = clothsim(grid_args("pages", "0.1"));
  EXPECT_EQ(again.exit_code, 0) << describe(again);
  EXPECT_TRUE(contains(again.out, "4 already complete"));
}

TEST_F(SweepTest, GridWritesFourCompleteFoldersAndAnIndex) {
  const Result result = clothsim(grid_args("grid"));
  ASSERT_EQ(result.exit_code, 0) << describe(result);
  EXPECT_TRUE(contains(result.out, "4 of 4 runs of this sweep complete"));

  // The first --param varies slowest; each run's scene holds its values.
  const std::vector<std::pair<double, int>> expected = {{40, 30}, {40, 60}, {80, 30}, {80, 60}};
  for (std::size_t i = 0; i < kRunFolders.size(); ++i) {
    const nlohmann::json run = summary("grid/" + kRunFolders[i]);
    EXPECT_EQ(run["status"], "completed") << kRunFolders[i];
    EXPECT_EQ(run["scene"]["springs"]["connector"]["stiffness"].get<double>(), expected[i].first) << kRunFolders[i];
    EXPECT_EQ(run["scene"]["output"]["fps"].get<int>(), expected[i].second) << kRunFolders[i];
    EXPECT_EQ(run["frames"].get<int>(), expected[i].second * 3 / 10 + 1) << kRunFolders[i];
  }

  const auto rows = read_csv(work_ / "grid" / "index.csv");
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[0][0], "run");
  for (std::size_t i = 0; i < kRunFolders.size(); ++i) {
    const nlohmann::json run = summary("grid/" + kRunFolders[i]);
    EXPECT_EQ(column(rows, i + 1, "folder"), kRunFolders[i]);
    EXPECT_EQ(column(rows, i + 1, "status"), "completed");
    EXPECT_EQ(std::stod(column(rows, i + 1, "springs.connector.stiffness")), expected[i].first);
    EXPECT_EQ(std::stoi(column(rows, i + 1, "output.fps")), expected[i].second);
    // The final energies read back to summary.json's doubles exactly.
    EXPECT_EQ(std::stod(column(rows, i + 1, "final_total")), run["energy"]["final"]["total"].get<double>());
    EXPECT_EQ(std::stod(column(rows, i + 1, "final_kinetic")), run["energy"]["final"]["kinetic"].get<double>());
    EXPECT_EQ(std::stod(column(rows, i + 1, "wall_seconds")), run["timings"]["wall_seconds"].get<double>());
  }
  // The frame rate only samples the motion (the states differ by the error tolerance); the
  // stiffness changes it: the connectors' energy by far more than that.
  const auto connector = [&](std::size_t row) { return std::stod(column(rows, row, "final_connector")); };
  EXPECT_NEAR(connector(2) / connector(1), 1.0, 1e-4);
  EXPECT_NEAR(connector(4) / connector(3), 1.0, 1e-4);
  EXPECT_GT(std::abs(connector(3) / connector(1) - 1.0), 0.1);
}

TEST_F(SweepTest, RunsEqualTheRunCommandWithSet) {
  ASSERT_EQ(clothsim(grid_args("grid")).exit_code, 0);
  const Result single = clothsim({"run", "paper-fig4", "--set", "springs.connector.stiffness=80", "--set",
                                  "output.fps=30", "--duration", "0.3", "--render", "none", "--out", "single"});
  ASSERT_EQ(single.exit_code, 0) << describe(single);
  for (const std::string& file : kStreamedFiles) {
    EXPECT_TRUE(read_text(work_ / "single" / file) == read_text(work_ / "grid/run-0002" / file)) << file;
  }
}

TEST_F(SweepTest, TwoShardsTogetherWriteTheSameFoldersAsTheWholeGrid) {
  ASSERT_EQ(clothsim(grid_args("whole")).exit_code, 0);
  std::vector<std::string> first = grid_args("sharded");
  first.insert(first.end(), {"--shard", "1/2"});
  const Result one = clothsim(first);
  ASSERT_EQ(one.exit_code, 0) << describe(one);
  // Shard 1 of 2 takes the even-numbered runs only.
  EXPECT_TRUE(fs::exists(work_ / "sharded/run-0000/summary.json"));
  EXPECT_TRUE(fs::exists(work_ / "sharded/run-0002/summary.json"));
  EXPECT_FALSE(fs::exists(work_ / "sharded/run-0001"));
  EXPECT_FALSE(fs::exists(work_ / "sharded/run-0003"));
  EXPECT_EQ(column(read_csv(work_ / "sharded/index.csv"), 2, "status"), "pending");

  std::vector<std::string> second = grid_args("sharded");
  second.insert(second.end(), {"--shard", "2/2", "--jobs", "2"});
  const Result two = clothsim(second);
  ASSERT_EQ(two.exit_code, 0) << describe(two);
  expect_same_runs("whole", "sharded");
  const auto rows = read_csv(work_ / "sharded/index.csv");
  ASSERT_EQ(rows.size(), 5u);
  for (std::size_t i = 1; i < rows.size(); ++i) EXPECT_EQ(column(rows, i, "status"), "completed") << i;
}

TEST_F(SweepTest, InterruptedSweepResumesWithoutRedoingFinishedRuns) {
  // Longer runs, with checkpoints, so that the interrupt finds run-0001 part way.
  std::vector<std::string> args = grid_args("grid", "1.5");
  args.insert(args.end(), {"--checkpoint-every", "0.25"});
  const pid_t pid = start(args);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(3);
  const auto second_run_started = [&] {
    std::error_code error;
    for (const auto& entry : fs::directory_iterator(work_ / "grid", error)) {
      if (entry.path().filename().string().starts_with("run-0001.partial-") &&
          fs::exists(entry.path() / "checkpoints", error) && !fs::is_empty(entry.path() / "checkpoints", error)) {
        return true;
      }
    }
    return false;
  };
  while (!second_run_started() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(second_run_started()) << "run-0001 never wrote a checkpoint";
  ::kill(pid, SIGINT);
  const Result stopped = wait_clothsim(pid, root_);
  ASSERT_EQ(stopped.exit_code, 130) << describe(stopped);
  EXPECT_TRUE(contains(stopped.out, "run the same command again"));
  EXPECT_EQ(summary("grid/run-0000")["status"], "completed");
  EXPECT_FALSE(fs::exists(work_ / "grid/run-0002"));
  EXPECT_EQ(column(read_csv(work_ / "grid/index.csv"), 2, "status"), "interrupted");
  struct stat before {};
  ASSERT_EQ(::stat((work_ / "grid/run-0000/positions.npy").c_str(), &before), 0);

  const Result again = clothsim(args);
  ASSERT_EQ(again.exit_code, 0) << describe(again);
  EXPECT_TRUE(contains(again.out, "1 already complete; 3 to run"));
  EXPECT_TRUE(contains(again.out, "run-0001 (springs.connector.stiffness=40, output.fps=60): completed (resumed)"));
  EXPECT_FALSE(contains(again.out, "run-0000 ("));
  struct stat after {};
  ASSERT_EQ(::stat((work_ / "grid/run-0000/positions.npy").c_str(), &after), 0);
  EXPECT_EQ(before.st_ino, after.st_ino);
  EXPECT_EQ(before.st_mtim.tv_nsec, after.st_mtim.tv_nsec);

  // The resumed and restarted runs equal an uninterrupted sweep's.
  std::vector<std::string> whole = grid_args("whole", "1.5");
  whole.insert(whole.end(), {"--checkpoint-every", "0.25", "--jobs", "2"});
  ASSERT_EQ(clothsim(whole).exit_code, 0);
  expect_same_runs("whole", "grid");
}

TEST_F(SweepTest, RunningACompleteSweepAgainRunsNothing) {
  ASSERT_EQ(clothsim(grid_args("grid")).exit_code, 0);
  const Result again = clothsim(grid_args("grid"));
  ASSERT_EQ(again.exit_code, 0) << describe(again);
  EXPECT_TRUE(contains(again.out, "4 already complete; 0 to run"));
  // Another grid into the same folder is refused.
  std::vector<std::string> other = grid_args("grid");
  other[5] = "output.fps=30,90";
  const Result refused = clothsim(other);
  EXPECT_EQ(refused.exit_code, 2) << describe(refused);
  EXPECT_TRUE(contains(refused.err, "holds another sweep"));
}

TEST_F(SweepTest, FailedRunsAreReportedAndKeptUnlessRetried) {
  // rk4 far past its stable step blows up (the run command's check): exit 1 and status "failed".
  const std::vector<std::string> args = {"sweep",
                                         "--paper-args",
                                         "11,11,1,4,1,1400,200,80,5,1",
                                         "--integrator",
                                         "rk4",
                                         "--param",
                                         "integrator.time_step=0.0002,0.01",
                                         "--duration",
                                         "0.2",
                                         "--render",
                                         "none",
                                         "--out",
                                         "grid"};
  const Result result = clothsim(args);
  EXPECT_EQ(result.exit_code, 1) << describe(result);
  EXPECT_TRUE(contains(result.out, "run-0001 (integrator.time_step=0.01): failed"));
  EXPECT_TRUE(contains(result.out, "the integration has blown up"));
  const auto rows = read_csv(work_ / "grid/index.csv");
  EXPECT_EQ(column(rows, 1, "status"), "completed");
  EXPECT_EQ(column(rows, 2, "status"), "failed");

  const Result again = clothsim(args);
  EXPECT_EQ(again.exit_code, 1) << describe(again);
  EXPECT_TRUE(contains(again.out, "1 failed before"));
  EXPECT_TRUE(contains(again.out, "0 to run"));
  std::vector<std::string> retry = args;
  retry.push_back("--retry-failed");
  const Result retried = clothsim(retry);
  EXPECT_EQ(retried.exit_code, 1) << describe(retried);
  EXPECT_TRUE(contains(retried.out, "1 to run"));
}

struct BadSweep {
  std::string name;
  std::vector<std::string> flags;
  std::string message;
};

void PrintTo(const BadSweep& c, std::ostream* out) { *out << c.name; }

class BadSweepTest : public SweepTest, public ::testing::WithParamInterface<BadSweep> {};

TEST_P(BadSweepTest, ExitsTwoNamingTheProblemAndWritesNothing) {
  std::vector<std::string> args = {"sweep", "paper-fig4", "--render", "none", "--out", "grid"};
  args.insert(args.end(), GetParam().flags.begin(), GetParam().flags.end());
  const Result result = clothsim(args);
  EXPECT_EQ(result.exit_code, 2) << describe(result);
  EXPECT_TRUE(contains(result.err, GetParam().message));
  EXPECT_TRUE(fs::is_empty(work_)) << "the sweep wrote something";
}

INSTANTIATE_TEST_SUITE_P(
    Sweep, BadSweepTest,
    ::testing::Values(
        BadSweep{"NoParam", {}, "needs at least one --param"},
        BadSweep{"UnknownKey", {"--param", "springs.nothing=1,2"}, "field 'springs.nothing': unknown field"},
        BadSweep{"ValueOutOfRange",
                 {"--param", "output.fps=30,0"},
                 "field 'output.fps': must be an integer in [1, 10000], got \"0\""},
        BadSweep{"EmptyValue", {"--param", "output.fps=30,,60"}, "has an empty value"},
        BadSweep{"RepeatedValue", {"--param", "output.fps=30,30"}, "lists the value 30 twice"},
        BadSweep{"RepeatedKey", {"--param", "output.fps=30", "--param", "output.fps=60"}, "swept by two --param"},
        BadSweep{"AlsoAFlag", {"--param", "output.fps=30,60", "--fps", "20"}, "is also given by --fps"},
        BadSweep{"ShardPastCount", {"--param", "output.fps=30", "--shard", "3/2"}, "--shard: K must be in [1, 2]"},
        BadSweep{"ShardZero", {"--param", "output.fps=30", "--shard", "0/2"}, "--shard: K must be in [1, 2]"},
        BadSweep{"ShardNotANumber", {"--param", "output.fps=30", "--shard", "a/2"}, "--shard: expects K/N"},
        BadSweep{"NoJobs", {"--param", "output.fps=30", "--jobs", "0"}, "--jobs: must be an integer in [1, 1024]"},
        BadSweep{"OpenBracket", {"--param", "environment.gravity=[0,-9.81,0],[0,-1"}, "bracket that is not closed"}),
    [](const ::testing::TestParamInfo<BadSweep>& param) { return param.param.name; });

}  // namespace
}  // namespace clothsim
