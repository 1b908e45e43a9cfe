// The pictures of a run (final.png and animation.mp4): the settings as text, as `clothsim run`'s
// --render, --size, --camera, --mesh, --show and --samples flags and the Python module's keyword
// arguments give them, checked into a RenderPlan; what the plan costs in memory; and one headless
// picture at a time (FrameRenderer), which the run's recorder (run/run_recorder.h) and the Python
// module's Simulation.render() both draw with, so a picture from Python is the run's picture.
//
// With render "none" nothing here touches OpenGL. A build without CLOTHSIM_BUILD_RENDER accepts
// only "none", and makes it the default (default_render_choice()).
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "core/vec3.h"
#include "model/cloth_model.h"

namespace clothsim {

namespace render {
struct Image;  // render/image.h
}

// "all" where this build renders, else "none".
const char* default_render_choice();

// The settings as typed; each names its flag in error messages.
struct RenderFlags {
  std::string render = default_render_choice();  // --render: all, image, video or none
  std::string size = "1280x720";                 // --size WxH, pixels
  std::string camera = "auto";                   // --camera: auto, follow or AZIMUTH,ELEVATION[,DISTANCE]
  std::string mesh = "particles";                // --mesh: particles or cell-centres
  std::string show;                              // --show: comma-separated overlays
  std::string samples = "4";                     // --samples: MSAA samples per pixel, [1, 16]
};

inline constexpr int kMinPictureSide = 16;    // pixels
inline constexpr int kMaxPictureSide = 8192;  // pixels

// The settings as a run's checkpoint keeps them (RunCheckpoint::options), and back; a key that is
// missing or not a string keeps the default.
std::string render_flags_json(const RenderFlags& flags);
RenderFlags render_flags_from_json(std::string_view text);

// The checked settings; opaque here so that callers compile without the render module.
struct RenderPlan;

// Parses and checks the flags; throws InputError naming the flag and the allowed values.
std::shared_ptr<const RenderPlan> parse_render_flags(const RenderFlags& flags);

// The memory the pictures of the plan take for the lattice of `counts` with `anchors` anchors
// (0 for render "none"): the graphics stack, the framebuffers, the recorder's copies of the model
// (one per frame held when `model_changes`: its springs tear, yield or crease, or anchors let go)
// and its frames, the sheet mesh and the driver's buffers.
std::size_t estimate_render_bytes(const RenderPlan& plan, const LatticeCounts& counts, std::size_t anchors,
                                  bool model_changes);

// What drawing the sheet of `counts` at width x height pixels with `samples` MSAA samples takes,
// headless or in a window: the graphics stack (EGL or GLX, Mesa; measured), the framebuffers, the
// sheet mesh and its vertex data, and the driver's copies of the vertex and index buffers
// (measured with llvmpipe; docs/performance.md, "Memory").
std::size_t picture_bytes(int width, int height, int samples, const LatticeCounts& counts);

// The files the plan writes, e.g. "final.png and animation.mp4", or "" for none.
std::string describe_render_outputs(const RenderPlan& plan);

inline constexpr std::string_view kImageFile = "final.png";
inline constexpr std::string_view kVideoFile = "animation.mp4";

// Draws frames headless as a plan says: an EGL context of the plan's size, the renderer, and the
// camera director (render/camera_director.h), which frames everything drawn so far, so frames must
// come in time order. The context is current on the thread that last called bind() (or the
// constructor); each call below binds it first, so one thread at a time may use the object, any
// thread. Without the render module the constructor throws OutputError.
class FrameRenderer {
 public:
  // Creates the context; throws OutputError (render::RenderError's message) when there is none.
  explicit FrameRenderer(std::shared_ptr<const RenderPlan> plan);
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  // Draws the sheet of `model` at `position` [particles], m, at simulated time `time`, s, and reads
  // it back into image(). Throws OutputError.
  void draw(const ClothModel& model, std::span<const Vec3> position, double time);
  // The last frame drawn (render/image.h: RGB, top row first).
  const render::Image& image() const;

  // Makes the context current on the calling thread, or on none.
  void bind();
  void release();
  // "1280x720, OpenGL 4.5 (Core Profile) Mesa 22.3.6, llvmpipe (...), EGL surfaceless, 4x MSAA".
  std::string description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clothsim
