// Tests of run/run_scene.h, the run driver shared by `clothsim run` and the Python module: the
// folder's frames are make_simulation()'s stepped to frame_time(k, fps), bit for bit; the observer
// hears what the command prints and stops the run; bad input writes nothing. The command's own
// output, flags and exit codes are tested end to end in tests/apps.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/npy.h"
#include "run/run_folders.h"
#include "run/run_scene.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene/scene_simulation.h"
#include "test_checks.h"

namespace clothsim {
namespace {

namespace fs = std::filesystem;

fs::path test_folder() { return checks::fresh_test_folder("run"); }

SceneSpec short_scene(double duration) {
  SceneSpec spec = builtin_scene("paper-fig5");
  spec.output.duration = duration;
  spec.output.fps = 30;
  return spec;
}

RunOptions data_only(const fs::path& out) {
  RunOptions options;
  options.out = out;
  options.info = RunInfo{"test", "test_run"};
  options.render.render = "none";
  return options;
}

// Records what the run reports; interrupts after `stop_after` frames (0: never).
class Recorder final : public RunObserver {
 public:
  void notice(const std::string& message) override { notices.push_back(message); }
  void frames_begin(double end_time) override { end = end_time; }
  void frame_done(double time, std::uint64_t /*accepted_steps*/) override { times.push_back(time); }
  void frames_end() override { ended = true; }
  bool interrupted() override { return stop_after > 0 && times.size() >= stop_after; }

  std::vector<std::string> notices;
  std::vector<double> times;
  double end = 0.0;
  bool ended = false;
  std::size_t stop_after = 0;
};

TEST(RunScene, FramesAreTheSimulationAtFrameTimesBitForBit) {
  const SceneSpec spec = short_scene(1.0);
  const fs::path out = test_folder() / "run";
  Recorder observer;
  RunOptions options = data_only(out);
  options.observer = &observer;
  const RunResult result = run_scene(spec, options);
  ASSERT_EQ(result.status, RunStatus::completed);
  EXPECT_EQ(result.out, out);
  EXPECT_EQ(result.frames, last_frame(spec.output) + 1);
  EXPECT_EQ(result.frames, 31u);
  EXPECT_EQ(observer.end, 1.0);
  EXPECT_TRUE(observer.ended);
  ASSERT_EQ(observer.times.size(), 30u);

  const NpyArray positions = read_npy((out / RunWriter::kPositionsFile).string());
  Simulation simulation = make_simulation(spec);
  std::vector<Vec3> frame(simulation.model().particle_count());
  for (std::uint64_t k = 0; k < result.frames; ++k) {
    ASSERT_TRUE(simulation.advance_to(frame_time(k, spec.output.fps)));
    if (k > 0) {
      EXPECT_EQ(observer.times[k - 1], frame_time(k, spec.output.fps));
    }
    read_npy_frame((out / RunWriter::kPositionsFile).string(), k, frame);
    for (std::size_t p = 0; p < frame.size(); ++p) {
      ASSERT_EQ(frame[p], simulation.state().position[p]) << "frame " << k << ", particle " << p;
    }
  }
  EXPECT_EQ(positions.shape[0], result.frames);
  // The result's simulation is the run's, at its last frame.
  EXPECT_EQ(result.simulation->state().position, simulation.state().position);
  EXPECT_EQ(result.last_time, 1.0);
}

TEST(RunScene, TheObserverStopsTheRunAfterACompleteFrame) {
  const fs::path out = test_folder() / "run";
  Recorder observer;
  observer.stop_after = 4;
  RunOptions options = data_only(out);
  options.observer = &observer;
  const RunResult result = run_scene(short_scene(1.0), options);
  EXPECT_EQ(result.status, RunStatus::interrupted);
  EXPECT_EQ(result.frames, 5u);  // frame 0 and four more
  EXPECT_TRUE(observer.ended);
  EXPECT_EQ(read_npy((out / RunWriter::kPositionsFile).string()).shape[0], 5u);
  EXPECT_TRUE(fs::exists(out / RunWriter::kSummaryFile));
}

TEST(RunScene, AFixedStepPastTheStableStepIsNoticedNotRefused) {
  SceneSpec spec = short_scene(0.1);
  spec.integrator.kind = IntegratorKind::rk4;
  spec.integrator.time_step = 0.01;
  Recorder observer;
  RunOptions options = data_only(test_folder() / "run");
  options.observer = &observer;
  run_scene(spec, options);
  ASSERT_FALSE(observer.notices.empty());
  EXPECT_EQ(observer.notices[0].rfind("warning: integrator.time_step = 0.01 s is above rk4's estimated stable step", 0),
            0u)
      << observer.notices[0];
}

TEST(RunScene, BadInputThrowsBeforeAnythingIsWritten) {
  const fs::path folder = test_folder();
  RunOptions options = data_only(folder / "run");
  options.render.render = "sometimes";
  EXPECT_THROW(run_scene(short_scene(0.1), options), InputError);
  // A scene above the memory the run may use: refused by the library, with the estimate in the
  // message, and nothing written either.
  options = data_only(folder / "run");
  options.max_memory = 1000;
  options.max_memory_source = "max_memory";
  try {
    run_scene(short_scene(0.1), options);
    ADD_FAILURE() << "a run allowed 1000 bytes went ahead";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("needs an estimated"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("max_memory allows 1000 bytes"), std::string::npos) << error.what();
  }
  EXPECT_FALSE(fs::exists(folder / "run"));
  // The same scene within a limit it fits runs.
  options.max_memory = std::uint64_t{1} << 34;
  EXPECT_EQ(run_scene(short_scene(0.1), options).status, RunStatus::completed);
  fs::remove_all(folder / "run");
  EXPECT_TRUE(fs::is_empty(folder));
}

TEST(RunScene, TheDefaultFolderIsTheScenesNameUnderOut) {
  SceneSpec spec;
  spec.name = "paper-fig5";
  EXPECT_EQ(default_output_folder(spec), "out/paper-fig5");
  spec.name = "a b/c";
  EXPECT_EQ(default_output_folder(spec), "out/a_b_c");
  spec.name = "..";
  EXPECT_EQ(default_output_folder(spec), "out/run");
}

TEST(RunScene, FrameTimesAreOneDivision) {
  EXPECT_EQ(frame_time(0, 60), 0.0);
  EXPECT_EQ(frame_time(7, 60), 7.0 / 60.0);
  EXPECT_EQ(frame_time(60, 60), 1.0);
  OutputSettings output;
  output.duration = 0.5;
  output.fps = 30;
  EXPECT_EQ(last_frame(output), 15u);
}

}  // namespace
}  // namespace clothsim
