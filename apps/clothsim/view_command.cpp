// `clothsim view`: the interactive viewer. Loads a scene with the same options as `clothsim run`
// (scene_options.h), checks everything (scene, script, flags) before a window opens, then hands
// over to the viewer (viewer/viewer_window.h). docs/viewer.md is the user's guide.
#include <charconv>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "core/error.h"
#include "memory_check.h"
#include "render/render_error.h"
#include "run/run_writer.h"
#include "scene_options.h"
#include "viewer/script.h"
#include "viewer/session.h"
#include "viewer/viewer_window.h"

namespace clothsim::cli {
namespace {

constexpr int kSmallestWindow = 64;   // pixels
constexpr int kLargestWindow = 8192;  // pixels
constexpr std::uint64_t kMostFrames = 1'000'000'000;

struct ViewOptions {
  SceneOptions scene;
  std::string script;
  std::uint64_t frames = 0;
  std::vector<std::string> screenshots;  // FRAME:PATH
  std::string screenshot_folder = ".";
  std::string dump_state;
  std::uint64_t benchmark_frames = 0;
  std::string size = "1280x800";
  int samples = -1;
  bool no_vsync = false;
  bool hide_panel = false;
  MemoryFlags memory;  // --max-memory (memory_check.h)
};

bool parse_whole(std::string_view text, std::uint64_t& value) {
  const char* end = text.data() + text.size();
  const auto [rest, error] = std::from_chars(text.data(), end, value);
  return error == std::errc() && rest == end && !text.empty();
}

std::pair<int, int> parse_size(const std::string& text) {
  const std::size_t x = text.find('x');
  std::uint64_t width = 0;
  std::uint64_t height = 0;
  if (x == std::string::npos || !parse_whole(std::string_view(text).substr(0, x), width) ||
      !parse_whole(std::string_view(text).substr(x + 1), height) || width < kSmallestWindow ||
      height < kSmallestWindow || width > kLargestWindow || height > kLargestWindow) {
    throw InputError("--size", "",
                     "expects WIDTHxHEIGHT in pixels, each in [64, 8192] (e.g. 1280x800), got \"" + text + "\"");
  }
  return {static_cast<int>(width), static_cast<int>(height)};
}

std::pair<std::uint64_t, std::string> parse_screenshot(const std::string& text) {
  const std::size_t colon = text.find(':');
  std::uint64_t frame = 0;
  if (colon == std::string::npos || !parse_whole(std::string_view(text).substr(0, colon), frame) ||
      colon + 1 == text.size() || frame > kMostFrames) {
    throw InputError(
        "--screenshot-at", "",
        "expects FRAME:PATH, a frame number in [0, 1e9] and a PNG path (e.g. 120:shot.png), got \"" + text + "\"");
  }
  return {frame, text.substr(colon + 1)};
}

int view(const ViewOptions& options) {
  // 1. Input, all of it checked before a window opens.
  const SceneSpec spec = make_scene(options.scene);
  viewer::ViewerOptions viewer_options;
  std::tie(viewer_options.width, viewer_options.height) = parse_size(options.size);
  if (!options.script.empty()) {
    viewer_options.script = viewer::load_script_file(options.script);
    viewer::check_script(*viewer_options.script, spec);
  }
  for (const std::string& screenshot : options.screenshots) {
    viewer_options.screenshots.push_back(parse_screenshot(screenshot));
  }
  if (options.scene.given("--frames") && (options.frames < 1 || options.frames > kMostFrames)) {
    throw InputError("--frames", "", "must be a whole number in [1, 1e9], got " + std::to_string(options.frames));
  }
  if (options.scene.given("--benchmark-frames") &&
      (options.benchmark_frames < 2 || options.benchmark_frames > kMostFrames)) {
    throw InputError("--benchmark-frames", "",
                     "must be a whole number in [2, 1e9], got " + std::to_string(options.benchmark_frames));
  }
  viewer_options.frames = options.frames;
  viewer_options.benchmark_frames = options.benchmark_frames;
  if (viewer_options.benchmark_frames > 0 && viewer_options.scripted()) {
    throw InputError("--benchmark-frames", "",
                     "measures the real-time viewer; it cannot be combined with --script, --frames or --screenshot-at");
  }
  viewer_options.screenshot_folder = options.screenshot_folder;
  viewer_options.dump_state = options.dump_state;
  if (options.scene.given("--samples")) {
    if (options.samples < 0 || options.samples > 16) {
      throw InputError("--samples", "", "must be a whole number in [0, 16], got " + std::to_string(options.samples));
    }
    viewer_options.samples = options.samples;
  }
  viewer_options.vsync = !options.no_vsync;
  viewer_options.show_panel = !options.hide_panel;
  check_view_memory(spec, viewer_options.width, viewer_options.height, options.memory);
  viewer::Session session(spec, MemoryAllowance{max_memory(options.memory), "--max-memory", true});

  // 2. The window.
  try {
    return viewer::run_viewer(session, viewer_options);
  } catch (const render::RenderError& error) {
    throw OutputError(error.what());
  }
}

std::string view_footer() {
  std::string text = wrap_text(
      "Opens a window on the scene and simulates it in real time (simulated time follows the wall clock; the "
      "panel says when the simulation cannot keep up). Drag particles with the mouse, pin them, change the "
      "springs, gravity, mass and integrator while it runs, watch the energy. A scripted run (--script, --frames, "
      "--screenshot-at) instead advances exactly 1/fps of simulated time per frame, so it gives the same frames "
      "on any machine. Controls, panel and script format: docs/viewer.md.",
      100, 0);
  text +=
      "\n\n"
      "Controls:\n"
      "  left drag: orbit; on a particle: drag it      right/middle drag: pan     wheel, +/-: zoom\n"
      "  right click or shift+click a particle: pin/unpin\n"
      "  space: play/pause   N: step one frame   R: reset   S: screenshot   F: frame the sheet\n"
      "  H: hide the panel   arrows: orbit (shift: pan)   Q, Esc: quit\n"
      "\n"
      "Examples:\n"
      "  clothsim view paper-fig4\n"
      "  clothsim view --paper-args 21,21,1,4,1,1400,200,80,5,1 --integrator rk4 --time-step 1e-3\n"
      "  clothsim view paper-fig5 --script drag.json --frames 240 --dump-state final.npy\n"
      "  xvfb-run -a clothsim view paper-fig4 --frames 120 --screenshot-at 120:fig4.png   # no display\n"
      "  clothsim view paper-fig4 --benchmark-frames 600      # prints fps and simulated/wall time\n"
      "\n"
      "Exit codes:\n"
      "  0    the window was closed, the script quit or the frame limit was reached\n"
      "  1    a scripted run's simulation failed (diagnosis on stderr)\n"
      "  2    bad input (scene, script, flag); no window was opened\n"
      "  3    no window could be opened (no display, no OpenGL 3.3), or a screenshot or --dump-state\n"
      "       could not be written";
  return text;
}

}  // namespace

Subcommand add_view_command(CLI::App& parent) {
  auto options = std::make_shared<ViewOptions>();
  CLI::App* app = parent.add_subcommand("view", "Open the interactive viewer on a scene");
  add_scene_options(*app, options->scene,
                    {{"--fps", "frames per simulated second of a scripted run (each frame advances 1/fps s)"},
                     {"--integrator"},
                     {"--rtol"},
                     {"--atol"},
                     {"--time-step"},
                     {"--gravity"},
                     {"--anchor"},
                     {"--threads"},
                     {"--self-collision"},
                     {"--thickness"},
                     {"--backend"},
                     {"--device"},
                     {"--precision"}});
  app->add_option("--script", options->script, "timed events to play (JSON; docs/viewer.md)")->type_name("FILE");
  app->add_option("--frames", options->frames, "stop after frame N (a scripted run: N frames of 1/fps s)")
      ->type_name("N");
  app->add_option("--screenshot-at", options->screenshots, "save frame N as a PNG (repeatable)")
      ->type_name("N:PATH")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app->add_option("--screenshot-folder", options->screenshot_folder,
                  "where the S key saves screenshots (default: the current folder)")
      ->type_name("DIR");
  app->add_option("--dump-state", options->dump_state, "write the final positions as .npy [particles, 3] at exit")
      ->type_name("FILE");
  app->add_option("--benchmark-frames", options->benchmark_frames,
                  "run N real-time frames without vsync, print fps and simulated/wall time, exit")
      ->type_name("N");
  app->add_option("--size", options->size, "window size in pixels (default 1280x800)")->type_name("WxH");
  app->add_option("--samples", options->samples,
                  "multisample anti-aliasing samples per pixel, 0 for none (default: 4 on a GPU, 0 on a "
                  "software renderer such as llvmpipe)")
      ->type_name("N");
  app->add_flag("--no-vsync", options->no_vsync, "draw as fast as possible instead of at the display's rate");
  app->add_flag("--hide-panel", options->hide_panel, "start with the panel hidden (H shows it)");
  add_memory_flag(*app, options->memory);
  app->footer(view_footer());
  return {app, [options] { return view(*options); }};
}

}  // namespace clothsim::cli
