// End-to-end tests of the clothsim tool's commands besides `run` (docs/cli.md): validate, scenes,
// params, devices and bench, every --help, and run --profile. Each runs the real executable in
// its own fresh folder (cli_test.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.h"
#include "cli_test.h"
#include "forces/lattice_kernel.h"
#include "scene/builtin_scenes.h"
#include "test_checks.h"

namespace clothsim {
namespace {

using nlohmann::json;
using Result = checks::ProcessResult;
using checks::read_text;
using checks::write_text;
using cli_harness::contains;
using cli_harness::describe;
using cli_harness::entries;
using cli_test::CliTest;

// ---------------------------------------------------------------------------------------------
// validate, scenes, params, help.

TEST_F(CliTest, ValidateReportsEachScene) {
  write_text(work_ / "good.json", R"({"name": "good", "paper_args": [5, 5, 1, 4, 1, 1400, 200, 80, 5, 1]})");
  write_text(work_ / "bad.json", R"({"lattice": {"rows": 0}})");
  const Result good = clothsim({"validate", "good.json", "paper-fig4"});
  EXPECT_EQ(good.exit_code, 0) << describe(good);
  EXPECT_TRUE(contains(good.out, "ok  good.json: 5x5 lattice, 25 particles, 40 connectors"));
  EXPECT_TRUE(contains(good.out, "ok  paper-fig4: 21x21 lattice, 441 particles, 840 connectors"));
  EXPECT_TRUE(contains(good.out, "1 anchor, rkf45, 20 s at 60 fps"));

  const Result bad = clothsim({"validate", "good.json", "bad.json"});
  EXPECT_EQ(bad.exit_code, 2) << describe(bad);
  EXPECT_TRUE(contains(bad.out, "ok  good.json"));
  EXPECT_TRUE(contains(bad.err, "clothsim: error: bad.json: field 'lattice.rows'"));
  EXPECT_TRUE(contains(bad.err, "[1, 4096]"));
}

TEST_F(CliTest, ScenesListsTheBuiltins) {
  const Result result = clothsim({"scenes"});
  EXPECT_EQ(result.exit_code, 0) << describe(result);
  // Every built-in, by name and with the start of its description.
  const std::vector<BuiltinScene> scenes = builtin_scenes();
  EXPECT_GE(scenes.size(), 14u);
  for (const BuiltinScene& scene : scenes) {
    EXPECT_TRUE(contains(result.out, scene.name)) << scene.name;
    EXPECT_TRUE(contains(result.out, scene.description.substr(0, 24))) << scene.name;
  }
}

TEST_F(CliTest, ParamsListsTheRegistry) {
  const Result result = clothsim({"params"});
  EXPECT_EQ(result.exit_code, 0) << describe(result);
  for (const char* piece : {"lattice.rows", "[1, 4096]", "springs.opposite.damping", "N m s/rad", "environment.gravity",
                            "integrator.method", "output.fps"}) {
    EXPECT_TRUE(contains(result.out, piece));
  }
}

TEST_F(CliTest, EveryHelpEndsWithExamples) {
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{{"--help"},
                                                                                    {"run", "--help"},
                                                                                    {"validate", "--help"},
                                                                                    {"scenes", "--help"},
                                                                                    {"params", "--help"},
                                                                                    {"devices", "--help"}}) {
    const Result result = clothsim(args);
    EXPECT_EQ(result.exit_code, 0) << args[0] << "\n" << describe(result);
    EXPECT_TRUE(contains(result.out, "Examples"));
  }
  const Result main_help = clothsim({"--help"});
  EXPECT_TRUE(contains(main_help.out, "Exit codes"));
  EXPECT_TRUE(contains(main_help.out, "130"));
  const Result version = clothsim({"--version"});
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_TRUE(contains(version.out, "clothsim "));
  EXPECT_TRUE(entries(work_).empty());
}

// `clothsim devices`: lavapipe at least where the Vulkan module is built (CI installs it), and
// without a Vulkan driver (the loader pointed at none) a clear error and exit 3.
TEST_F(CliTest, DevicesListsTheVulkanDevices) {
  const Result result = clothsim({"devices"});
#if defined(CLOTHSIM_HAVE_VULKAN)
  EXPECT_EQ(result.exit_code, 0) << describe(result);
  EXPECT_TRUE(result.out.starts_with("0: ")) << result.out;
  EXPECT_TRUE(contains(result.out, "device memory, float64 ")) << result.out;
#else
  EXPECT_EQ(result.exit_code, 3) << describe(result);
  EXPECT_TRUE(contains(result.err, "built without Vulkan")) << result.err;
#endif
  EXPECT_TRUE(entries(work_).empty());
}

TEST_F(CliTest, DevicesWithoutAVulkanDriverExitsThree) {
  ::setenv("VK_ICD_FILENAMES", "/nonexistent/no_driver.json", 1);
  ::setenv("VK_DRIVER_FILES", "/nonexistent/no_driver.json", 1);
  const Result result = clothsim({"devices"});
  ::unsetenv("VK_ICD_FILENAMES");
  ::unsetenv("VK_DRIVER_FILES");
  EXPECT_EQ(result.exit_code, 3) << describe(result);
  EXPECT_TRUE(contains(result.err, "clothsim: error: ")) << result.err;
  EXPECT_TRUE(result.out.empty()) << result.out;
}

TEST_F(CliTest, NoSubcommandIsBadInput) {
  const Result result = clothsim({});
  EXPECT_EQ(result.exit_code, 2) << describe(result);
  EXPECT_TRUE(contains(result.err, "clothsim: error: "));
}

// ---------------------------------------------------------------------------------------------
// clothsim bench and run --profile

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  bool quoted = false;
  for (char c : line) {
    if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      fields.push_back(field);
      field.clear();
    } else {
      field += c;
    }
  }
  fields.push_back(field);
  return fields;
}

TEST_F(CliTest, BenchWritesOneCsvRowPerCase) {
  const Result result = clothsim({"bench", "--sizes", "4,6", "--integrators", "rkf45,symplectic-euler", "--seconds",
                                  "0.05", "--sim-cap", "0.05", "--csv", "bench.csv"});
  ASSERT_EQ(result.exit_code, 0) << describe(result);
  EXPECT_TRUE(contains(result.out, "6x6"));
  EXPECT_TRUE(contains(result.out, "symplectic-euler"));
  EXPECT_TRUE(contains(result.out, "GFLOP/s"));
  EXPECT_TRUE(contains(result.out, "%peak"));
  EXPECT_EQ(entries(work_), (std::set<std::string>{"bench.csv"}));
  std::istringstream csv(read_text(work_ / "bench.csv"));
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  const std::vector<std::string> header = split_csv_line(line);
  const auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return static_cast<std::size_t>(it - header.begin());
  };
  std::vector<std::vector<std::string>> rows;
  while (std::getline(csv, line)) rows.push_back(split_csv_line(line));
  ASSERT_EQ(rows.size(), 4u);  // sizes x integrators, sizes outer
  const std::vector<std::pair<std::string, std::string>> expected = {
      {"4", "rkf45"}, {"4", "symplectic-euler"}, {"6", "rkf45"}, {"6", "symplectic-euler"}};
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), header.size());
    EXPECT_EQ(rows[i][column("rows")], expected[i].first);
    EXPECT_EQ(rows[i][column("integrator")], expected[i].second);
    EXPECT_EQ(rows[i][column("status")], "ok");
    // RKF45 on `auto` by default, its precision chosen frame by frame (sim/precision_choice.h).
    EXPECT_EQ(rows[i][column("kernel")], expected[i].second == "rkf45" ? "lattice-auto" : "lattice");
    EXPECT_GT(std::stod(rows[i][column("force_evaluations")]), 0.0);
    EXPECT_GT(std::stod(rows[i][column("evaluations_per_second")]), 0.0);
    EXPECT_GT(std::stod(rows[i][column("memory_bytes")]), 0.0);
    // The roofline: the lattice kernel's counted operations, its achieved rate, the probed peak
    // and the share, which no kernel can push past the peak (1.5: the margin of a noisy probe).
    EXPECT_EQ(std::stod(rows[i][column("flops_per_particle")]), kLatticeKernelFlopsPerParticle);
    EXPECT_GT(std::stod(rows[i][column("peak_gflops")]), 0.0);
    EXPECT_GT(std::stod(rows[i][column("achieved_gflops")]), 0.0);
    const double share = std::stod(rows[i][column("peak_share")]);
    EXPECT_GT(share, 0.0);
    EXPECT_LT(share, 1.5);
    EXPECT_NEAR(share, std::stod(rows[i][column("achieved_gflops")]) / std::stod(rows[i][column("peak_gflops")]),
                1e-12 * share);
    // Each case stops at the simulated-time cap (0.05 s rounded up to whole 60 fps frames) or
    // at the wall budget, whichever comes first.
    EXPECT_LE(std::stod(rows[i][column("simulated_seconds")]), 0.05 + 1e-9);
  }
}

TEST_F(CliTest, BenchRejectsBadFlagsAndRunsNothing) {
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"bench", "--sizes", "1", "--csv", "b.csv"},
                                             {"bench", "--sizes", "25,x", "--csv", "b.csv"},
                                             {"bench", "--integrators", "euler", "--csv", "b.csv"},
                                             {"bench", "--seconds", "0", "--csv", "b.csv"},
                                             {"bench", "--sizes", "4", "--csv", "nosuch/b.csv"}}) {
    const Result result = clothsim(args);
    EXPECT_EQ(result.exit_code, 2) << args[1] << "\n" << describe(result);
    const std::string flag = args.back() == "nosuch/b.csv" ? "--csv" : args[1];
    EXPECT_TRUE(contains(result.err, "clothsim: error: " + flag)) << describe(result);
    EXPECT_FALSE(contains(result.out, "lattice "));  // no table: nothing ran
    EXPECT_TRUE(entries(work_).empty());
  }
}

TEST_F(CliTest, ProfileListsEveryPhaseOfTheRun) {
  const Result result = small_run("run", {"--duration", "0.2", "--profile"});
  ASSERT_EQ(result.exit_code, 0) << describe(result);
  for (const char* phase : {"forces", "integration", "stage sums", "solution and error", "events", "checks", "output",
                            "total", "evaluations"}) {
    EXPECT_TRUE(contains(result.out, phase)) << phase;
  }
  const json s = summary("run");
  const json& phases = s["timings"]["integration_phases"];
  // RKF45's solution update and error norm are one pass, timed as one phase.
  EXPECT_EQ(phases.size(), 2u);
  EXPECT_TRUE(phases.contains("stage sums"));
  EXPECT_TRUE(phases.contains("solution and error"));
  double sum = 0.0;
  for (const auto& [name, seconds] : phases.items()) sum += seconds.get<double>();
  EXPECT_LE(sum, s["timings"]["integration"].get<double>() * (1 + 1e-12));
  EXPECT_GT(s["memory_bytes"].get<double>(), 0.0);
  // Fixed-step methods list only the phases they have.
  const Result rk4 = small_run("rk4", {"--duration", "0.1", "--integrator", "rk4", "--time-step", "1e-4", "--profile"});
  ASSERT_EQ(rk4.exit_code, 0) << describe(rk4);
  EXPECT_TRUE(contains(rk4.out, "solution update"));
  EXPECT_FALSE(contains(rk4.out, "solution and error"));
}

}  // namespace
}  // namespace clothsim
