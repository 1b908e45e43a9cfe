// The recorder of a run's pictures: each output frame rendered headless (run/render_plan.h,
// FrameRenderer) into final.png and animation.mp4.
//
// Order within a run (run/run_scene.cpp): the settings are parsed with the other input, before
// anything is written (bad values are InputError); the recorder is constructed before the
// simulation starts and before the output folder exists, so a machine without EGL or ffmpeg fails
// at once (OutputError, with a message suggesting --render none) instead of after a long run;
// begin() starts ffmpeg writing into the partial output folder and a worker thread that renders;
// frame() queues each output frame for it; finish() waits for the worker, writes final.png and
// waits for ffmpeg, before the folder is renamed into place. A run that dies on the way leaves
// nothing: the partial folder goes, ffmpeg with it. With render "none" it does nothing.
#pragma once

#include <filesystem>
#include <memory>
#include <span>
#include <string>

#include "core/vec3.h"
#include "model/cloth_model.h"
#include "run/render_plan.h"
#include "run/run_writer.h"

namespace clothsim {

class RunRecorder {
 public:
  // Creates the headless OpenGL context and checks that ffmpeg runs, as the plan needs. Throws
  // OutputError when either is unavailable. With render "none" it does nothing. `model` is the
  // model the run starts from.
  RunRecorder(std::shared_ptr<const RenderPlan> plan, const ClothModel& model);
  ~RunRecorder();
  RunRecorder(const RunRecorder&) = delete;
  RunRecorder& operator=(const RunRecorder&) = delete;

  // Starts the video (ffmpeg writing `folder`/animation.mp4 at `fps`). Throws OutputError.
  void begin(const std::filesystem::path& folder, int fps);
  // Queues one output frame for rendering and the video, drawn as `model` is now (its topology,
  // its anchors, its colliders): the positions are copied, and the model too when its revision
  // has moved since the last frame. Waits while 3 frames are already queued. Throws OutputError
  // if rendering or ffmpeg failed.
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

}  // namespace clothsim
