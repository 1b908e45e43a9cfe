// `--backend vulkan` end to end (docs/gpu.md): a run on the device writes the folder a CPU run
// writes, with the backend recorded in its scene; what the backend cannot run, no device and a
// scene too large for the device are refused with exit 2 and nothing written. And the bench on the
// device. Without the Vulkan backend in the build, asking for it is the same clear refusal.
#include <gtest/gtest.h>

#include <array>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.h"
#include "test_checks.h"

namespace clothsim {
namespace {

namespace fs = std::filesystem;
using checks::read_text;
using cli_harness::contains;
using cli_harness::describe;
using cli_harness::entries;
using Result = checks::ProcessResult;

class BackendTest : public cli_harness::ToolTest {
 protected:
  BackendTest() : ToolTest("backend") {}

  // A refusal: exit 2, the message, nothing written.
  void expect_refused(const Result& result, const std::string& message) const {
    EXPECT_EQ(result.exit_code, 2) << describe(result);
    EXPECT_TRUE(contains(result.err, message));
    EXPECT_TRUE(entries(work_).empty()) << "written: " << entries(work_).size() << " paths";
  }
};

// Float32 forces on the CPU (tests/sim/test_mixed_precision.cpp holds their accuracy): the scene
// records what was asked, the summary what ran, with `auto` resolved from the tolerances and, where
// it starts in float32, its choice frame by frame.
TEST_F(BackendTest, TheCpuRunsFloat32ForcesAndAutoResolvesThem) {
  for (const auto& [asked, tolerance, ran] : std::vector<std::array<std::string, 3>>{
           {"float32", "1e-6", "float32"}, {"auto", "1e-6", "float32"}, {"auto", "1e-8", "float64"}}) {
    const std::string out = asked + "-" + tolerance;
    const Result result = clothsim({"run", "paper-fig5", "--duration", "0.05", "--render", "none", "--precision", asked,
                                    "--rtol", tolerance, "--out", out});
    ASSERT_EQ(result.exit_code, 0) << describe(result);
    const nlohmann::json scene = nlohmann::json::parse(read_text(work_ / out / "scene.json"));
    EXPECT_EQ(scene["precision"], asked);
    const nlohmann::json summary = nlohmann::json::parse(read_text(work_ / out / "summary.json"));
    EXPECT_EQ(summary["integrator"]["precision"], ran) << out;
    // `auto` that starts in float32 chooses frame by frame (sim/precision_choice.h) and says how.
    const nlohmann::json& choice = summary["integrator"]["precision_choice"];
    if (asked == "auto" && ran == "float32") {
      EXPECT_EQ(choice["float32_windows"], 3) << out;  // 0.05 s: a window a frame
      EXPECT_EQ(choice["float64_windows"], 0) << out;
      EXPECT_GE(choice["rest_steps"], 1) << out;
      EXPECT_GT(choice["largest_drift"], 0.0) << out;
      EXPECT_DOUBLE_EQ(choice["drift_limit"], 0.25e-6) << out;
    } else {
      EXPECT_TRUE(choice.is_null()) << out;
    }
  }
}

#if defined(CLOTHSIM_HAVE_VULKAN)

TEST_F(BackendTest, ARunOnTheDeviceWritesTheCpusFolder) {
  const std::vector<std::string> common = {"run", "paper-fig5", "--duration", "0.1", "--render", "none"};
  std::vector<std::string> device = common;
  device.insert(device.end(), {"--backend", "vulkan", "--out", "device"});
  const Result result = clothsim(device);
  ASSERT_EQ(result.exit_code, 0) << describe(result);
  std::vector<std::string> cpu = common;
  cpu.insert(cpu.end(), {"--out", "cpu"});
  ASSERT_EQ(clothsim(cpu).exit_code, 0);
  std::set<std::string> cpu_files = entries(work_ / "cpu");
  EXPECT_EQ(entries(work_ / "device"), cpu_files);
  const nlohmann::json scene = nlohmann::json::parse(read_text(work_ / "device" / "scene.json"));
  EXPECT_EQ(scene["backend"], "vulkan");
  EXPECT_TRUE(scene["precision"].is_null());  // the backend's default, float32
  const nlohmann::json summary = nlohmann::json::parse(read_text(work_ / "device" / "summary.json"));
  EXPECT_EQ(summary["status"], "completed");
  // The positions, 7 frames of 121 particles, agree with the CPU's within float32's (the library
  // tests hold the trajectories: tests/gpu).
  EXPECT_EQ(read_text(work_ / "device" / "positions.npy").size(), read_text(work_ / "cpu" / "positions.npy").size());
}

TEST_F(BackendTest, WhatTheDeviceDoesNotRunIsRefused) {
  // Refused on every backend: the message ends with its own advice, not with backend cpu's.
  const Result float32 =
      clothsim({"run", "tear-pull", "--backend", "vulkan", "--precision", "float32", "--render", "none"});
  expect_refused(float32,
                 "the vulkan backend does not run float32 (precision) with implicit-euler (integrator.method), "
                 "whose Newton solve needs float64 forces; use precision float64 or auto");
  EXPECT_FALSE(contains(float32.err, "use backend cpu")) << float32.err;
  expect_refused(clothsim({"run", "paper-fig5", "--backend", "vulkan", "--integrator", "imex", "--render", "none"}),
                 "field 'backend': the vulkan backend does not run imex (integrator.method) yet");
  expect_refused(clothsim({"run", "tear-pull", "--precision", "float32", "--render", "none"}),
                 "the cpu backend does not run float32 (precision) with implicit-euler (integrator.method)");
  expect_refused(clothsim({"run", "paper-fig5", "--precision", "float16", "--render", "none"}),
                 "field 'precision': must be one of float64, float32, auto");
  expect_refused(clothsim({"run", "paper-fig5", "--backend", "gpu", "--render", "none"}),
                 "field 'backend': must be one of cpu, vulkan, got \"gpu\"");
}

TEST_F(BackendTest, NoDeviceAndTooLargeAreRefusedBeforeAnythingIsWritten) {
  expect_refused(clothsim({"run", "paper-fig5", "--backend", "vulkan", "--device", "9", "--render", "none"}),
                 "the vulkan backend cannot run: no Vulkan device 9");
  // 3,000 x 3,000 particles need more than lavapipe's 2 GiB, and more than any device this test
  // runs on that has less than 8 GiB.
  const Result large = clothsim({"run", "--paper-args", "3000,3000,1,4,1,1400,200,80,5,1", "--backend", "vulkan",
                                 "--precision", "float64", "--render", "none", "--duration", "0.01"});
  if (large.exit_code != 0) {
    expect_refused(large, "MiB of device memory");
  }
  ::setenv("VK_ICD_FILENAMES", "/nonexistent/no_driver.json", 1);
  ::setenv("VK_DRIVER_FILES", "/nonexistent/no_driver.json", 1);
  const Result none = clothsim({"run", "paper-fig5", "--backend", "vulkan", "--render", "none"});
  ::unsetenv("VK_ICD_FILENAMES");
  ::unsetenv("VK_DRIVER_FILES");
  expect_refused(none, "the vulkan backend cannot run: no Vulkan device");
}

TEST_F(BackendTest, TheBenchRunsOnTheDevice) {
  const Result result = clothsim(
      {"bench", "--backend", "vulkan", "--sizes", "9", "--seconds", "0.2", "--sim-cap", "0.05", "--csv", "bench.csv"});
  ASSERT_EQ(result.exit_code, 0) << describe(result);
  const std::string csv = read_text(work_ / "bench.csv");
  // Every method the backend runs: the explicit ones in its default float32, implicit Euler in
  // float64 (its only precision); imex is the CPU's.
  EXPECT_TRUE(contains(csv, ",rkf45,vulkan-float32,"));
  EXPECT_TRUE(contains(csv, ",rk4,vulkan-float32,"));
  EXPECT_TRUE(contains(csv, ",symplectic-euler,vulkan-float32,"));
  EXPECT_TRUE(contains(csv, ",implicit-euler,vulkan-float64,")) << csv;
  EXPECT_FALSE(contains(csv, "imex"));
  const Result refused = clothsim({"bench", "--backend", "vulkan", "--integrators", "imex"});
  EXPECT_EQ(refused.exit_code, 2) << describe(refused);
  EXPECT_TRUE(contains(refused.err, "does not run imex"));
}

// --stage-passes chooses how the explicit stages run on the device, and the kernel column says so;
// a value it does not know, or another backend, is refused.
TEST_F(BackendTest, TheBenchChoosesTheStagePasses) {
  for (const char* passes : {"split", "fused", "chained"}) {
    const Result result =
        clothsim({"bench", "--backend", "vulkan", "--sizes", "9", "--integrators", "rkf45", "--seconds", "0.2",
                  "--sim-cap", "0.05", "--stage-passes", passes, "--csv", "bench.csv"});
    ASSERT_EQ(result.exit_code, 0) << describe(result);
    EXPECT_TRUE(contains(read_text(work_ / "bench.csv"), std::string(",rkf45,vulkan-float32-") + passes + ","))
        << passes;
  }
  const Result unknown = clothsim({"bench", "--backend", "vulkan", "--stage-passes", "twice"});
  EXPECT_EQ(unknown.exit_code, 2) << describe(unknown);
  EXPECT_TRUE(contains(unknown.err, "expected split, fused or chained, got 'twice'")) << unknown.err;
  const Result cpu = clothsim({"bench", "--stage-passes", "chained"});
  EXPECT_EQ(cpu.exit_code, 2) << describe(cpu);
  EXPECT_TRUE(contains(cpu.err, "applies to the vulkan backend only")) << cpu.err;
}

#else

TEST_F(BackendTest, WithoutVulkanInTheBuildTheBackendIsRefused) {
  expect_refused(clothsim({"run", "paper-fig5", "--backend", "vulkan", "--render", "none"}),
                 "built without the Vulkan backend");
}

#endif

}  // namespace
}  // namespace clothsim
