// The checked picture settings (run/render_plan.h), for the run module's own files: callers
// outside it see RenderPlan only as an opaque type, so that they compile without the render
// module.
#pragma once

#include "run/render_plan.h"

#if CLOTHSIM_HAVE_RENDER
#include "render/camera_director.h"
#include "render/render_options.h"
#endif

namespace clothsim {

struct RenderPlan {
  bool image = false;  // final.png
  bool video = false;  // animation.mp4
  int width = 1280;    // pixels
  int height = 720;
  int samples = 4;  // MSAA samples per pixel
#if CLOTHSIM_HAVE_RENDER
  render::CameraChoice camera;
  render::RenderOptions options;
#endif
};

}  // namespace clothsim
