// Headless OpenGL: an EGL context without any window system, rendering into an offscreen
// framebuffer object that is read back into memory. This is how `clothsim run` makes images and
// video on machines without a display (CI, servers), on a GPU where there is one and on Mesa's
// llvmpipe software rasteriser where there is none.
//
// Display: EGL_MESA_platform_surfaceless through eglGetPlatformDisplayEXT (no X, no Wayland, no
// GBM device needed), else the first EGL device (EGL_EXT_platform_device; NVIDIA's headless
// driver), else eglGetDisplay(EGL_DEFAULT_DISPLAY). Context: desktop OpenGL 3.3 core, made current
// with no surface (EGL_KHR_surfaceless_context). Nothing here selects a software renderer: with
// a GPU and its EGL driver installed, the GPU is used.
//
// Target: an FBO with an RGBA8 colour and a depth renderbuffer, multisampled (up to 8 samples,
// fewer if the driver offers fewer) and resolved with glBlitFramebuffer into a single-sampled
// FBO that glReadPixels reads back.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "render/image.h"
#include "render/render_error.h"

namespace clothsim::render {

class HeadlessContext {
 public:
  // Creates the EGL display and context and makes it current on this thread, with a
  // width x height offscreen target bound. Throws RenderError naming what failed (no EGL
  // display, no OpenGL 3.3 core context, FBO incomplete).
  HeadlessContext(int width, int height, int samples = 4);
  ~HeadlessContext();
  HeadlessContext(const HeadlessContext&) = delete;
  HeadlessContext& operator=(const HeadlessContext&) = delete;

  int width() const;
  int height() const;
  int samples() const;  // MSAA samples of the target actually obtained (1: none)

  // Makes the context current on the calling thread and binds the offscreen target for drawing
  // (draw calls go there). A context is current on at most one thread: to hand it to another
  // thread, release() it on this one first.
  void bind();
  // Makes no context current on the calling thread (if this one was current there).
  void release();
  // Resolves the target and reads it into `image` (RGB, top row first).
  void read(Image& image);

  // "OpenGL 4.5 (Core Profile) Mesa 22.3.6, llvmpipe (LLVM 15.0.6, 256 bits), EGL surfaceless"
  std::string description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clothsim::render
