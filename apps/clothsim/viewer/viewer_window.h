// The viewer's window: GLFW for the window and input, the renderer (render/renderer.h) for the
// sheet, Dear ImGui for the panel. It maps mouse and keys onto the Session and the Camera, paces
// the simulation to the wall clock (FramePacer) or, in a scripted run, to a fixed simulated time
// per frame, and writes screenshots and the final state. docs/viewer.md describes the controls.
//
// A scripted run (--script, --frames or --screenshot-at) advances exactly 1 / output.fps of
// simulated time per frame while playing and spends no wall-time budget, so its frames and its
// final state are the same on any machine; an interactive run follows the wall clock.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "viewer/script.h"
#include "viewer/session.h"

namespace clothsim::viewer {

struct ViewerOptions {
  int width = 1280;  // window size, pixels
  int height = 800;
  std::optional<Script> script;
  std::uint64_t frames = 0;  // stop after this frame (0: run until closed or a "quit" event)
  std::vector<std::pair<std::uint64_t, std::string>> screenshots;  // frame, PNG path (--screenshot-at)
  std::string screenshot_folder = ".";                             // where the screenshot key saves
  std::string dump_state;                                          // positions .npy written at exit ("" for none)
  std::uint64_t benchmark_frames = 0;                              // measure this many real-time frames, print, exit
  // Multisample anti-aliasing samples per pixel; 0 turns it off; -1 chooses: 4 on a GPU, 0 on a
  // software renderer (Mesa's llvmpipe draws 4x MSAA about 5 times slower than no MSAA).
  int samples = -1;
  bool vsync = true;
  bool show_panel = true;

  bool scripted() const { return script.has_value() || frames > 0 || !screenshots.empty(); }
};

// Opens the window and runs until it is closed, a script quits or the frame limit is reached.
// Returns the exit code: 0, or 1 when a scripted run's simulation failed. Throws
// render::RenderError when no window or OpenGL 3.3 context can be had, OutputError when a
// scripted screenshot or the state dump cannot be written.
int run_viewer(Session& session, const ViewerOptions& options);

}  // namespace clothsim::viewer
