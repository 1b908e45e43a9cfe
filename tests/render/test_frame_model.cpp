// The run's pictures show the model as it is at each frame (run/run_recorder.h): a sheet that
// tears is drawn in pieces, an anchor that lets go loses its marker. The oracle is the run's
// frames drawn again, one by one, from a simulation stepped to the same frame times with the
// model it has at each (FrameRenderer, the recorder's own renderer): final.png must be that
// drawing to the byte, and the video's last frame must be nearer to it than to the same frames
// drawn with the model the run started from, which is what the pictures showed before, where the
// two drawings differ.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "render/image.h"
#include "run/render_plan.h"
#include "run/run_scene.h"
#include "scene/builtin_scenes.h"
#include "scene/scene_simulation.h"

namespace clothsim {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 320;
constexpr int kHeight = 240;

RenderFlags small_pictures() {
  RenderFlags flags;
  flags.render = "all";
  flags.size = std::to_string(kWidth) + "x" + std::to_string(kHeight);
  flags.samples = "1";
  flags.camera = "0,89";  // degrees, from above: the floor shows wherever the sheet is not
  return flags;
}

// The run's frames drawn again: `live` with the simulation's model at each frame, `stale` with
// the model the simulation started from.
struct Redrawn {
  render::Image live;
  render::Image stale;
};

Redrawn redraw_frames(const SceneSpec& spec, const RenderFlags& flags) {
  const std::shared_ptr<const RenderPlan> plan = parse_render_flags(flags);
  FrameRenderer live(plan);
  Redrawn out;
  Simulation simulation = make_simulation(spec);
  const ClothModel initial = simulation.model();
  std::vector<std::pair<std::vector<Vec3>, double>> frames;
  for (std::uint64_t k = 0; k <= last_frame(spec.output); ++k) {
    if (k > 0) {
      EXPECT_TRUE(simulation.advance_to(frame_time(k, spec.output.fps)));
    }
    live.draw(simulation.model(), simulation.state().position, simulation.state().time);
    frames.emplace_back(simulation.state().position, simulation.state().time);
  }
  out.live = live.image();
  live.release();
  FrameRenderer stale(plan);
  for (const auto& [position, time] : frames) stale.draw(initial, position, time);
  out.stale = stale.image();
  return out;
}

// The video's last frame as RGB, decoded by ffmpeg.
render::Image last_video_frame(const fs::path& video, const fs::path& png) {
  const std::string command = "ffmpeg -loglevel error -y -sseof -0.5 -i '" + video.string() +
                              "' -update 1 -frames:v 100 '" + png.string() + "'";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  return render::read_png(png.string());
}

// Mean absolute difference per channel between `a` and `b`, over the pixels where `live` and
// `stale` differ by more than the video's coding noise: where the two models draw differently.
double difference_where_models_differ(const render::Image& a, const render::Image& b, const Redrawn& redrawn) {
  const auto at = [](const render::Image& image, int x, int y, int c) { return int{image.pixel(x, y)[c]}; };
  double sum = 0.0;
  std::size_t count = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      int models = 0;
      for (int c = 0; c < 3; ++c) models = std::max(models, std::abs(at(redrawn.live, x, y, c) - at(redrawn.stale, x, y, c)));
      if (models < 48) continue;
      for (int c = 0; c < 3; ++c) sum += std::abs(at(a, x, y, c) - at(b, x, y, c));
      ++count;
    }
  }
  EXPECT_GT(count, 0u);
  return sum / (3.0 * static_cast<double>(std::max<std::size_t>(count, 1)));
}

std::size_t differing_pixels(const render::Image& a, const render::Image& b) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < a.rgb.size(); i += 3) {
    if (a.rgb[i] != b.rgb[i] || a.rgb[i + 1] != b.rgb[i + 1] || a.rgb[i + 2] != b.rgb[i + 2]) ++count;
  }
  return count;
}

void expect_pictures_of_each_frames_model(const SceneSpec& spec, const std::string& name) {
  const fs::path root = fs::path(CLOTHSIM_TEST_TMPDIR) / "frame_model" / name;
  fs::remove_all(root);
  fs::create_directories(root);
  RunOptions options;
  options.out = root / "run";
  options.render = small_pictures();
  const RunResult result = run_scene(spec, options);
  ASSERT_EQ(result.status, RunStatus::completed);
  ASSERT_GT(result.simulation->model().revision, 0u) << name << " must change its model during the run";

  const Redrawn redrawn = redraw_frames(spec, options.render);
  // The change shows: drawn with the first model, the last frame looks different.
  ASSERT_GT(differing_pixels(redrawn.live, redrawn.stale), std::size_t{200}) << name;

  const render::Image final_png = render::read_png((result.out / "final.png").string());
  ASSERT_EQ(final_png.width, kWidth);
  ASSERT_EQ(final_png.height, kHeight);
  EXPECT_EQ(differing_pixels(final_png, redrawn.live), 0u) << name << ": final.png is not the last frame's model";

  const render::Image video = last_video_frame(result.out / "animation.mp4", root / "last-video-frame.png");
  ASSERT_GE(video.width, kWidth);
  ASSERT_GE(video.height, kHeight);
  const double to_live = difference_where_models_differ(video, redrawn.live, redrawn);
  const double to_stale = difference_where_models_differ(video, redrawn.stale, redrawn);
  EXPECT_LT(3.0 * to_live, to_stale) << name << ": the video's last frame is " << to_live
                                     << " from the frame's model and " << to_stale << " from the first model";
}

TEST(FrameModel, ATornSheetIsDrawnInTwoPieces) {
  SceneSpec spec = builtin_scene("tear-pull");  // torn across by 0.6 s
  spec.output.fps = 10;
  expect_pictures_of_each_frames_model(spec, "tear-pull");
}

TEST(FrameModel, AReleasedAnchorLosesItsMarker) {
  SceneSpec spec = builtin_scene("paper-crease");  // rows 19 and 20 let go at 0.8 s
  spec.output.duration = 1.2;
  spec.output.fps = 10;
  expect_pictures_of_each_frames_model(spec, "paper-crease");
}

}  // namespace
}  // namespace clothsim
