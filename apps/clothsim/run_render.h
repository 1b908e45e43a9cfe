// The pictures of `clothsim run`: the --render, --size, --camera, --mesh, --show and --samples
// flags, and
// the recorder that renders each output frame headlessly into final.png and animation.mp4.
//
// Order within a run (run_command.cpp): the flags are parsed with the other input, before
// anything is written (bad values exit 2); the recorder is constructed before the simulation
// starts and before the output folder exists, so a machine without EGL or ffmpeg fails at once
// (exit 3, with a message suggesting --render none) instead of after a long run; begin() starts
// ffmpeg writing into the partial output folder and a worker thread that renders; frame() queues
// each output frame for it; finish() waits for the worker, writes final.png and waits for ffmpeg,
// before the folder is renamed into place. A run that
// dies on the way leaves nothing: the partial folder goes, ffmpeg with it.
//
// With --render none nothing here touches OpenGL: no context is created (batch runs on
// machines without any graphics stack). A build without CLOTHSIM_BUILD_RENDER accepts only
// --render none, and makes it the default.
#pragma once

#include <filesystem>
#include <memory>
#include <span>
#include <string>

#include <CLI/CLI.hpp>

#include "core/vec3.h"
#include "io/run_writer.h"
#include "model/cloth_model.h"

namespace clothsim::cli {

// The flag values as typed.
struct RenderFlags {
  std::string render;
  std::string size;
  std::string camera;
  std::string mesh;
  std::string show;
  std::string samples;
};

// Registers the flags on `app`.
void add_render_flags(CLI::App& app, RenderFlags& flags);

// The parsed flags; opaque here so that run_command.cpp compiles without the render module.
struct RenderPlan;

// Parses and checks the flags; throws InputError naming the flag and the allowed values.
std::shared_ptr<const RenderPlan> parse_render_flags(const RenderFlags& flags);

// The memory the pictures of the plan take for the lattice of `counts` with `anchors` anchors
// (0 for --render none): the graphics stack, the framebuffers, the recorder's copy of the model
// and its frames, the sheet mesh and the driver's buffers (memory_check.h).
std::size_t estimate_render_bytes(const RenderPlan& plan, const LatticeCounts& counts, std::size_t anchors);

// The files the plan writes, e.g. "final.png and animation.mp4", or "" for none.
std::string describe_render_outputs(const RenderPlan& plan);

class RunRecorder {
 public:
  // Creates the headless OpenGL context and checks that ffmpeg runs, as the plan needs. Throws
  // OutputError (exit 3) when either is unavailable. With --render none it does nothing. The
  // model is copied for the rendering thread: its topology must not change during the run (the
  // model argument of frame() is not read; it is there for when events change the sheet).
  RunRecorder(std::shared_ptr<const RenderPlan> plan, const ClothModel& model);
  ~RunRecorder();
  RunRecorder(const RunRecorder&) = delete;
  RunRecorder& operator=(const RunRecorder&) = delete;

  // Starts the video (ffmpeg writing `folder`/animation.mp4 at `fps`). Throws OutputError.
  void begin(const std::filesystem::path& folder, int fps);
  // Queues one output frame (its positions are copied) for rendering and the video; waits while
  // 3 frames are already queued. Throws OutputError if rendering or ffmpeg failed.
  void frame(const ClothModel& model, std::span<const Vec3> position, double time);
  // Writes final.png (the last frame) into the writer's partial folder, finishes the video, and
  // records both in summary.json "files". Throws OutputError.
  void finish(RunWriter& writer);

  bool active() const;
  // "1280x720, OpenGL 4.5 (Core Profile) Mesa 22.3.6, llvmpipe (...), EGL surfaceless, 4x MSAA".
  std::string description() const;
  // Wall time spent rendering and encoding so far, s; frames rendered.
  double seconds() const;
  long frames() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

inline constexpr std::string_view kImageFile = "final.png";
inline constexpr std::string_view kVideoFile = "animation.mp4";

}  // namespace clothsim::cli
