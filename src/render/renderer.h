// Draws a sheet with OpenGL 3.3 core: shaded two-sided surface, anchors, obstacles (colliders),
// ground grid and optional spring and wireframe overlays. Design and lighting model: docs/rendering.md.
//
// The Renderer owns GL objects (shaders, buffers) and so needs a current OpenGL 3.3 core context
// for its whole life, from construction to destruction: a window's (the viewer's GLFW context)
// or a headless one (render/headless.h). It draws into whatever framebuffer is bound, so the
// same code path serves the window and offscreen images. All GL entry points come from libepoxy,
// which resolves them for GLX, EGL and WGL contexts alike.
//
// Per frame, draw() rebuilds the mesh on the CPU (model/sheet_mesh: positions, area-weighted
// normals) and streams it into one vertex buffer (GL_STREAM_DRAW, orphaned each frame); the
// triangle index buffer is uploaded again only when the mesh's topology changes (grid size, mode,
// a tear: SheetMesh::topology_version). A torn sheet is drawn from the split mesh, so its pieces
// part on screen; broken springs are not drawn. The surface is drawn without face culling,
// and the fragment shader flips the normal and picks the back colour where gl_FrontFacing is
// false, so both sides are lit.
#pragma once

#include <memory>
#include <span>

#include "core/vec3.h"
#include "model/cloth_model.h"
#include "render/camera.h"
#include "render/render_error.h"
#include "render/render_options.h"

namespace clothsim::render {

class Renderer {
 public:
  // Needs a current OpenGL >= 3.3 core context; throws RenderError otherwise, or when a shader
  // fails to compile or link (the message holds the driver's log).
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Clears and draws the sheet of `model` at `position` [particle_count()], m, into the bound
  // framebuffer's rectangle (0, 0, width, height), with the model's colliders where their paths
  // put them at `time` (s; the state's time). Non-finite positions are drawn as they are (the GPU
  // discards such triangles); they never raise.
  void draw(const ClothModel& model, std::span<const Vec3> position, const RenderOptions& options, const Camera& camera,
            int width, int height, double time = 0.0);

  // The ground height draw() uses when options.ground_height is unset: the lowest y of
  // `position` minus a small gap (5% of the sheet's extent, at least one spacing).
  static double automatic_ground_height(const ClothModel& model, std::span<const Vec3> position);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clothsim::render
