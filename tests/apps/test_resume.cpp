// Checkpoints and resume, end to end (docs/cli.md "Checkpoints and resume"): runs of the real tool
// killed with SIGKILL at several points, during checkpoint writes among them, and resumed, must
// leave the output an uninterrupted run leaves, bit for bit (the exports too); a damaged newest
// checkpoint falls back to the one before it; what cannot be resumed is refused with a message
// and exit 2; a run into a folder whose earlier run died reports the leftover and replaces it.
#include <signal.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.h"
#include "run/run_exports.h"
#include "test_checks.h"

namespace clothsim {
namespace {

namespace fs = std::filesystem;
using checks::contains;
using checks::read_text;
using cli_harness::describe;
using cli_harness::wait_clothsim;
using Result = checks::ProcessResult;
using Clock = std::chrono::steady_clock;

// The files that must come out the same, bit for bit.
const std::vector<std::string> kStreamedFiles = {"positions.npy", "velocities.npy", "energy.csv"};

struct ResumeCase {
  std::string name;
  std::vector<std::string> scene;  // SCENE and its flags
  std::string checkpoint_every;    // s
};

void PrintTo(const ResumeCase& c, std::ostream* out) { *out << c.name; }

// Each feature whose state a checkpoint must carry: the adaptive controller (paper-fig4, with
// self-collision on, though its sheet never comes within the thickness of itself in its 20 s),
// fixed-step explicit methods, implicit Euler's warm start with tearing and yielding (tear-pull),
// creasing (paper-crease), resting contact with friction (tablecloth), and the sheet held out of
// itself (pile: the self pass pushes 12,300 pairs apart over its first 0.4 s).
const std::vector<ResumeCase> kResumeCases = {
    {"Rkf45SelfCollision", {"paper-fig4", "--duration", "6"}, "0.5"},
    {"Rk4", {"paper-fig5", "--integrator", "rk4", "--time-step", "2e-4", "--duration", "4"}, "0.1"},
    {"SymplecticEuler",
     {"paper-fig5", "--integrator", "symplectic-euler", "--time-step", "1e-4", "--duration", "4"},
     "0.1"},
    {"ImplicitEulerTearing", {"tear-pull"}, "0.1"},
    {"ImplicitEulerCreasing", {"paper-crease", "--duration", "1.2"}, "0.1"},
    {"ImplicitEulerResting", {"tablecloth", "--duration", "0.6"}, "0.05"},
    {"Imex", {"paper-fig5", "--integrator", "imex", "--duration", "4"}, "0.1"},
    {"SelfContactsOnTheHost", {"pile", "--duration", "0.4"}, "0.1"},
};

class ResumeTest : public cli_harness::ToolTest {
 protected:
  ResumeTest() : ToolTest("resume") {}

  // `clothsim run SCENE... --out OUT --checkpoint-every EVERY`, without pictures.
  static std::vector<std::string> run_args(const ResumeCase& c, const std::string& out) {
    std::vector<std::string> args = {"run"};
    args.insert(args.end(), c.scene.begin(), c.scene.end());
    args.insert(args.end(), {"--out", out, "--checkpoint-every", c.checkpoint_every, "--render", "none",
                             "--no-progress", "--quiet"});
    return args;
  }

  fs::path partial(const std::string& out, pid_t pid) const {
    return work_ / (out + ".partial-" + std::to_string(pid));
  }

  // The newest checkpoint's file name in `folder`/checkpoints ("" if none).
  static std::string newest_checkpoint(const fs::path& folder) {
    std::string best;
    std::error_code error;
    for (const auto& entry : fs::directory_iterator(folder / "checkpoints", error)) {
      const std::string name = entry.path().filename().string();
      if (name.ends_with(".ckpt") && name.front() != '.' && name > best) best = name;
    }
    return best;
  }

  // Waits (up to 2 minutes) until `folder` holds a checkpoint newer than `after` ("" for any);
  // returns its name.
  static std::string wait_for_checkpoint(const fs::path& folder, const std::string& after) {
    const auto deadline = Clock::now() + std::chrono::seconds(120);
    while (newest_checkpoint(folder) <= after && Clock::now() < deadline) std::this_thread::yield();
    return newest_checkpoint(folder);
  }

  // Waits for a checkpoint newer than `after`, then kills `pid` with SIGKILL. With `in_write`,
  // first waits on (up to 2 s more) for a checkpoint's temporary file to appear, and kills while
  // it is there, during the write. Returns the newest checkpoint's name at the kill.
  static std::string kill_after_checkpoint(pid_t pid, const fs::path& folder, const std::string& after, bool in_write) {
    const auto writing = [&] {
      std::error_code error;
      for (const auto& entry : fs::directory_iterator(folder / "checkpoints", error)) {
        if (entry.path().filename().string().find(".tmp-") != std::string::npos) return true;
      }
      return false;
    };
    wait_for_checkpoint(folder, after);
    if (in_write) {
      const auto give_up = Clock::now() + std::chrono::seconds(2);
      while (!writing() && Clock::now() < give_up) std::this_thread::yield();
    }
    ::kill(pid, SIGKILL);
    return newest_checkpoint(folder);
  }

  void expect_same_output(const std::string& a, const std::string& b) const {
    for (const std::string& file : kStreamedFiles) {
      const std::string left = read_text(work_ / a / file);
      ASSERT_FALSE(left.empty()) << a << "/" << file;
      EXPECT_TRUE(left == read_text(work_ / b / file)) << file << " differs between " << a << " and " << b;
    }
  }

  // Every file of `a` but its checkpoints is in `b` with the same bytes, and summary.json holds
  // the same values but for what measures the process: the wall times, the command line, the
  // resumption itself, and the capacity of buffers that grow with the run (memory_bytes: a
  // resumed run grows its own from the checkpoint on).
  void expect_same_folder_and_summary(const std::string& a, const std::string& b) const {
    for (const fs::directory_entry& entry : fs::directory_iterator(work_ / a)) {
      const std::string file = entry.path().filename().string();
      if (!entry.is_regular_file() || file == "summary.json") continue;
      EXPECT_TRUE(read_text(entry.path()) == read_text(work_ / b / file)) << file << " differs between " << a << " and "
                                                                          << b;
    }
    nlohmann::json left = summary(a);
    nlohmann::json right = summary(b);
    for (const char* key : {"timings", "command_line", "resumed", "memory_bytes"}) {
      left.erase(key);
      right.erase(key);
    }
    EXPECT_EQ(left.flatten().dump(1), right.flatten().dump(1));
  }
};

class KilledRunTest : public ResumeTest, public ::testing::WithParamInterface<ResumeCase> {};

TEST_P(KilledRunTest, ResumesToTheUninterruptedOutputBitForBit) {
  const ResumeCase& c = GetParam();
  const Result full = clothsim(run_args(c, "full"));
  ASSERT_EQ(full.exit_code, 0) << describe(full);

  // Killed after its first checkpoint, resumed; the resumed run killed during a later checkpoint
  // write (or just after a checkpoint, if no write is caught), resumed again, to the end.
  const pid_t first = start(run_args(c, "part"));
  const std::string at_first_kill = kill_after_checkpoint(first, partial("part", first), "", false);
  ASSERT_EQ(wait_clothsim(first, root_).exit_code, 128 + SIGKILL) << "the run ended before it was killed";
  ASSERT_FALSE(at_first_kill.empty());

  const pid_t second = start({"run", "--resume", partial("part", first).filename().string(), "--no-progress"});
  const std::string at_second_kill = kill_after_checkpoint(second, partial("part", second), at_first_kill, true);
  const Result killed = wait_clothsim(second, root_);
  ASSERT_EQ(killed.exit_code, 128 + SIGKILL) << describe(killed);
  EXPECT_TRUE(contains(killed.err, "resuming")) << describe(killed);
  EXPECT_FALSE(fs::exists(partial("part", first))) << "the resumed run takes the partial folder over";

  const Result resumed = clothsim({"run", "--resume", partial("part", second).filename().string(), "--no-progress"});
  ASSERT_EQ(resumed.exit_code, 0) << describe(resumed);
  EXPECT_FALSE(fs::exists(partial("part", second)));
  expect_same_output("full", "part");
  EXPECT_EQ(summary("part")["status"], "completed");
  EXPECT_EQ(summary("part")["frames"], summary("full")["frames"]);
  EXPECT_TRUE(summary("part").contains("resumed"));
  EXPECT_EQ(summary("part")["integrator"]["accepted_steps"], summary("full")["integrator"]["accepted_steps"]);
  expect_same_folder_and_summary("full", "part");
}

INSTANTIATE_TEST_SUITE_P(Scenes, KilledRunTest, ::testing::ValuesIn(kResumeCases),
                         [](const ::testing::TestParamInfo<ResumeCase>& param) { return param.param.name; });

const ResumeCase kQuick = {"Quick", {"paper-fig5", "--duration", "20"}, "0.5"};

TEST_F(ResumeTest, DamagedNewestCheckpointFallsBackToThePreviousOne) {
  ASSERT_EQ(clothsim(run_args(kQuick, "full")).exit_code, 0);
  for (const std::string damage : {"flip", "truncate"}) {
    const std::string out = "part-" + damage;
    const pid_t pid = start(run_args(kQuick, out));
    const fs::path folder = partial(out, pid);
    kill_after_checkpoint(pid, folder, wait_for_checkpoint(folder, ""), false);
    ASSERT_EQ(wait_clothsim(pid, root_).exit_code, 128 + SIGKILL) << "the run ended before it was killed";
    std::vector<fs::path> checkpoints;
    for (const auto& entry : fs::directory_iterator(folder / "checkpoints")) {
      if (entry.path().extension() == ".ckpt") checkpoints.push_back(entry.path());
    }
    std::sort(checkpoints.begin(), checkpoints.end());
    ASSERT_EQ(checkpoints.size(), 2u) << "two checkpoints are kept";
    const fs::path newest = checkpoints.back();
    if (damage == "flip") {
      std::fstream file(newest, std::ios::in | std::ios::out | std::ios::binary);
      file.seekg(static_cast<std::streamoff>(fs::file_size(newest) / 2));
      const int byte = file.get();
      file.seekp(static_cast<std::streamoff>(fs::file_size(newest) / 2));
      file.put(static_cast<char>(byte ^ 0x10));
    } else {
      fs::resize_file(newest, fs::file_size(newest) - 100);
    }
    const Result resumed = clothsim({"run", "--resume", folder.filename().string(), "--no-progress"});
    ASSERT_EQ(resumed.exit_code, 0) << describe(resumed);
    EXPECT_TRUE(contains(resumed.err, "skipping a damaged checkpoint")) << describe(resumed);
    EXPECT_TRUE(contains(resumed.err, newest.filename().string())) << describe(resumed);
    EXPECT_TRUE(contains(resumed.err, damage == "flip" ? "checksum" : "truncated")) << describe(resumed);
    EXPECT_TRUE(contains(resumed.err, checkpoints.front().filename().string())) << describe(resumed);
    expect_same_output("full", out);
  }
}

TEST_F(ResumeTest, InterruptedRunResumesFromItsFolder) {
  ASSERT_EQ(clothsim(run_args(kQuick, "full")).exit_code, 0);
  const pid_t pid = start(run_args(kQuick, "part"));
  wait_for_checkpoint(partial("part", pid), "");
  ::kill(pid, SIGINT);
  const Result interrupted = wait_clothsim(pid, root_);
  ASSERT_EQ(interrupted.exit_code, 130) << describe(interrupted);
  EXPECT_TRUE(contains(interrupted.err, "clothsim run --resume part")) << describe(interrupted);
  EXPECT_EQ(summary("part")["status"], "interrupted");
  const auto frames = summary("part")["frames"].get<std::uint64_t>();
  // The interrupted run's last frame has its checkpoint, so nothing is computed twice.
  EXPECT_TRUE(fs::exists(
      work_ / "part" / "checkpoints" /
      ("frame_" + std::string(6 - std::to_string(frames - 1).size(), '0') + std::to_string(frames - 1) + ".ckpt")));

  const Result resumed = clothsim({"run", "--resume", "part", "--no-progress"});
  ASSERT_EQ(resumed.exit_code, 0) << describe(resumed);
  expect_same_output("full", "part");
  EXPECT_EQ(summary("part")["status"], "completed");
  EXPECT_EQ(summary("part")["command_line"],
            summary("full")["command_line"].get<std::string>().replace(
                summary("full")["command_line"].get<std::string>().find("full"), 4, "part"));
}

// The exports come out of a killed and resumed run as out of an uninterrupted one: the point
// cache and the OBJ sequence cut back to the checkpoint and streamed on, rest.obj, final.glb and
// animation.glb (from the whole positions.npy) written at the end (docs/exports.md).
TEST_F(ResumeTest, ExportsOfAResumedRunAreTheUninterruptedRunsBitForBit) {
  const ResumeCase exported = {
      "Exported", {"paper-fig5", "--duration", "6", "--export", "pc2,obj-sequence,gltf,gltf-animation"}, "0.5"};
  ASSERT_EQ(clothsim(run_args(exported, "full")).exit_code, 0);
  const pid_t pid = start(run_args(exported, "part"));
  kill_after_checkpoint(pid, partial("part", pid), "", false);
  ASSERT_EQ(wait_clothsim(pid, root_).exit_code, 128 + SIGKILL) << "the run ended before it was killed";
  const Result resumed = clothsim({"run", "--resume", partial("part", pid).filename().string(), "--no-progress"});
  ASSERT_EQ(resumed.exit_code, 0) << describe(resumed);
  expect_same_output("full", "part");
  const auto frames = summary("full")["frames"].get<std::size_t>();
  for (const std::string& file :
       {std::string("animation.pc2"), std::string("rest.obj"), std::string("final.glb"), std::string("animation.glb"),
        RunExports::frame_file_name(0), RunExports::frame_file_name(frames - 1)}) {
    const std::string left = read_text(work_ / "full" / file);
    ASSERT_FALSE(left.empty()) << "full/" << file;
    EXPECT_TRUE(left == read_text(work_ / "part" / file)) << file << " differs between full and part";
  }
  EXPECT_FALSE(fs::exists(work_ / "part" / RunExports::frame_file_name(frames)));
}

TEST_F(ResumeTest, UnfinishedCheckpointWriteIsIgnoredAndRemoved) {
  ASSERT_EQ(clothsim(run_args(kQuick, "full")).exit_code, 0);
  const pid_t pid = start(run_args(kQuick, "part"));
  const fs::path folder = partial("part", pid);
  const std::string last = kill_after_checkpoint(pid, folder, "", false);
  ASSERT_EQ(wait_clothsim(pid, root_).exit_code, 128 + SIGKILL);
  // What a kill in the middle of the next write leaves: half a temporary file.
  const fs::path checkpoint = folder / "checkpoints" / last;
  const fs::path unfinished = folder / "checkpoints" / (".frame_999999.ckpt.tmp-" + std::to_string(pid));
  fs::copy_file(checkpoint, unfinished);
  fs::resize_file(unfinished, fs::file_size(checkpoint) / 2);

  const Result resumed = clothsim({"run", "--resume", (folder / "checkpoints" / last).string(), "--no-progress"});
  ASSERT_EQ(resumed.exit_code, 0) << describe(resumed);
  EXPECT_FALSE(contains(resumed.err, "damaged")) << describe(resumed);
  expect_same_output("full", "part");
  for (const auto& entry : fs::directory_iterator(work_ / "part" / "checkpoints")) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
  }
}

TEST_F(ResumeTest, WhatCannotBeResumedIsRefused) {
  ASSERT_EQ(clothsim(run_args(kQuick, "done")).exit_code, 0);
  // A run without checkpoints, stopped early (as far as its summary says).
  ASSERT_EQ(
      clothsim({"run", "paper-fig6", "--duration", "0.1", "--out", "plain", "--render", "none", "--quiet"}).exit_code,
      0);
  checks::write_text(work_ / "plain" / "summary.json", R"({"clothsim_version": "x", "status": "interrupted"})");
  struct Refusal {
    std::vector<std::string> args;
    std::vector<std::string> pieces;
  };
  const std::vector<Refusal> refusals = {
      {{"run", "--resume", "nosuch"}, {"--resume", "nosuch", "does not exist"}},
      {{"run", "--resume", "done"}, {"--resume", "done", "complete", "nothing to resume"}},
      {{"run", "--resume", "plain"}, {"--resume", "plain", "no checkpoints", "--checkpoint-every"}},
      {{"run", "--resume", "done/scene.json"}, {"--resume", "not a checkpoint"}},
      {{"run", "paper-fig5", "--resume", "done"}, {"--resume", "SCENE", "cannot be combined"}},
      {{"run", "--resume", "done", "--fps", "30"}, {"--resume", "--fps", "cannot be combined"}},
      {{"run", "--resume", "done", "--out", "x"}, {"--resume", "--out", "cannot be combined"}},
  };
  for (const Refusal& refusal : refusals) {
    const Result result = clothsim(refusal.args);
    EXPECT_EQ(result.exit_code, 2) << describe(result);
    for (const std::string& piece : refusal.pieces) EXPECT_TRUE(contains(result.err, piece)) << describe(result);
  }
  // A checkpoint of one scene does not go into another's folder, even of the same lattice.
  const std::string checkpoint = newest_checkpoint(work_ / "done");
  fs::create_directories(work_ / "plain" / "checkpoints");
  fs::copy_file(work_ / "done" / "checkpoints" / checkpoint, work_ / "plain" / "checkpoints" / checkpoint);
  const Result mismatch = clothsim({"run", "--resume", "plain"});
  EXPECT_EQ(mismatch.exit_code, 2) << describe(mismatch);
  EXPECT_TRUE(contains(mismatch.err, "another scene")) << describe(mismatch);
}

TEST_F(ResumeTest, NewRunReportsALeftoverAndReplacesIt) {
  const pid_t pid = start(run_args(kQuick, "out"));
  const fs::path leftover = partial("out", pid);
  kill_after_checkpoint(pid, leftover, "", false);
  ASSERT_EQ(wait_clothsim(pid, root_).exit_code, 128 + SIGKILL);
  ASSERT_TRUE(fs::exists(leftover));

  const Result again =
      clothsim({"run", "paper-fig5", "--duration", "0.2", "--out", "out", "--render", "none", "--no-progress"});
  ASSERT_EQ(again.exit_code, 0) << describe(again);
  EXPECT_TRUE(contains(again.err, leftover.filename().string())) << describe(again);
  EXPECT_TRUE(contains(again.err, "clothsim run --resume")) << describe(again);
  EXPECT_TRUE(contains(again.err, "deleted")) << describe(again);
  EXPECT_FALSE(fs::exists(leftover));
}

}  // namespace
}  // namespace clothsim
