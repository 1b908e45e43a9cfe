// The OpenGL 3.3 core renderer; what it draws and why is in docs/rendering.md. Its GLSL sources
// are in shaders.h, its programs and buffers in gl_objects.h, the triangles of the colliders and
// the marker sphere in tessellation.h.
//
// Passes, in order, into the bound framebuffer:
//   1. clear to the background colour;
//   2. ground: one quad at the ground height, grid lines computed per fragment (anti-aliased
//      with fwidth) and faded out with distance so the plane has no visible edge;
//   3. colliders (obstacles): triangles built on the CPU each frame at the colliders' positions
//      at the frame's time (spheres and capsules tessellated, boxes and meshes with flat faces,
//      planes as a large quad around the sheet, in the ground's colour), lit like the sheet in
//      one neutral colour. An
//      upward horizontal plane is the floor: it replaces the ground grid, which would otherwise
//      float above or hide below it;
//   4. sheet: indexed triangles, per-vertex positions and normals streamed each frame, two-sided
//      lighting in the fragment shader; pushed back slightly (polygon offset) so overlay lines
//      on the surface win the depth test;
//   5. overlays: wireframe (the triangles again as lines), connector springs (lines), radial
//      springs (arcs near their centre particle, see below);
//   6. anchor markers and the highlighted particle: instanced shaded spheres, drawn once with the
//      depth test and once more where hidden (depth GREATER) at reduced opacity, so a marker shows
//      through a sheet folded over it.
//
// Lighting (fragment shader, linear colour space, sRGB in and out): a hemisphere ambient term, a
// key light and a weaker fill light, both fixed relative to the camera (upper right and left of
// the viewer) so that whichever side faces the camera is lit, plus a Blinn-Phong highlight from
// the key light. The colours in RenderOptions are sRGB, as a colour picker shows them; they are
// converted to linear light for the lighting and back to sRGB on output.
//
// Radial springs are drawn as arcs of radius r around their centre particle, from the direction
// of one connector to the other: a quarter arc (r = 0.25 L) for an adjacent pair, a half circle
// (r = 0.4 L) standing up along the surface normal for an opposite pair (whose bending plane is
// the one the sheet folds in). Both are polylines of kArcSegments segments built on the CPU.
#include "render/renderer.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "model/collider.h"
#include "model/sheet_mesh.h"
#include "render/gl_objects.h"
#include "render/shaders.h"
#include "render/tessellation.h"

namespace clothsim::render {
namespace {

constexpr int kArcSegments = 6;
constexpr double kPi = std::numbers::pi;

}  // namespace

struct Renderer::Impl {
  GLuint lit_sheet = 0;
  GLuint lit_sphere = 0;
  GLuint flat_line = 0;
  GLuint ground = 0;

  Buffers sheet;
  Buffers sphere;
  GLuint sphere_instances = 0;
  GLsizei sphere_index_count = 0;
  Buffers lines;
  Buffers ground_quad;
  Buffers colliders;
  GLsizei plane_vertex_count = 0;  // the colliders' vertex buffer holds the planes' vertices first

  // The mesh and its triangles as uploaded; re-uploaded when the mesh's topology changes (a new
  // grid, a new mode, a tear).
  SheetMesh mesh;
  std::uint64_t uploaded_topology = std::numeric_limits<std::uint64_t>::max();

  // Per-frame scratch, kept to avoid allocation.
  std::vector<float> vertex_data;
  std::vector<float> line_data;
  std::vector<float> instance_data;
  std::vector<std::uint32_t> edge_indices;

  void draw_lines(const std::vector<float>& data, const Colour& colour, const Mat4& view_projection) {
    if (data.empty()) return;
    glUseProgram(flat_line);
    set_matrix(flat_line, "view_projection", view_projection);
    set_colour(flat_line, "line_colour", colour);
    lines.upload(data, {0}, 3);
    glDrawArrays(GL_LINES, 0, static_cast<GLsizei>(data.size() / 3));
  }
};

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {
  if (epoxy_gl_version() < 33 || epoxy_is_desktop_gl() == 0) {
    throw RenderError("the renderer needs desktop OpenGL 3.3 or later; the current context has " +
                      std::string(epoxy_is_desktop_gl() ? "OpenGL " : "OpenGL ES ") +
                      std::to_string(epoxy_gl_version() / 10) + "." + std::to_string(epoxy_gl_version() % 10));
  }
  Impl& impl = *impl_;
  impl.lit_sheet = link_program(kSheetVertexShader, kLitFragmentShader, "sheet");
  impl.lit_sphere = link_program(kSphereVertexShader, kLitFragmentShader, "marker");
  impl.flat_line = link_program(kLineVertexShader, kLineFragmentShader, "line");
  impl.ground = link_program(kGroundVertexShader, kGroundFragmentShader, "ground");
  impl.sheet.create();
  impl.sphere.create();
  impl.lines.create();
  impl.ground_quad.create();
  impl.colliders.create();
  glGenBuffers(1, &impl.sphere_instances);

  std::vector<float> sphere_vertices;
  std::vector<std::uint32_t> sphere_indices;
  make_sphere(16, 10, sphere_vertices, sphere_indices);
  impl.sphere.upload(sphere_vertices, {0}, 3);
  impl.sphere.upload_elements(sphere_indices.data(), sphere_indices.size() * sizeof(std::uint32_t));
  impl.sphere_index_count = static_cast<GLsizei>(sphere_indices.size());
  glBindBuffer(GL_ARRAY_BUFFER, impl.sphere_instances);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
  glVertexAttribDivisor(1, 1);
  glBindVertexArray(0);
}

Renderer::~Renderer() {
  Impl& impl = *impl_;
  glDeleteBuffers(1, &impl.sphere_instances);
  impl.ground_quad.destroy();
  impl.colliders.destroy();
  impl.lines.destroy();
  impl.sphere.destroy();
  impl.sheet.destroy();
  for (const GLuint program : {impl.lit_sheet, impl.lit_sphere, impl.flat_line, impl.ground}) glDeleteProgram(program);
}

double Renderer::automatic_ground_height(const ClothModel& model, std::span<const Vec3> position) {
  double lowest = std::numeric_limits<double>::infinity();
  double low_x = lowest, high_x = -lowest, low_z = lowest, high_z = -lowest;
  for (const Vec3& p : position) {
    if (!is_finite(p)) continue;
    lowest = std::min(lowest, p.y);
    low_x = std::min(low_x, p.x);
    high_x = std::max(high_x, p.x);
    low_z = std::min(low_z, p.z);
    high_z = std::max(high_z, p.z);
  }
  if (!std::isfinite(lowest)) return 0.0;
  const double extent = std::max(high_x - low_x, high_z - low_z);
  return lowest - std::max(0.05 * extent, model.spacing);
}

void Renderer::draw(const ClothModel& model, std::span<const Vec3> position, const RenderOptions& options,
                    const Camera& camera, int width, int height, double time) {
  if (position.size() != model.particle_count()) {
    throw RenderError("Renderer::draw: " + std::to_string(position.size()) + " positions for a model of " +
                      std::to_string(model.particle_count()) + " particles");
  }
  if (width <= 0 || height <= 0) return;
  Impl& impl = *impl_;
  const double aspect = static_cast<double>(width) / height;
  const Mat4 view_projection = camera.view_projection(aspect);
  const Vec3 eye = camera.eye();
  // Lights fixed to the camera: key from the upper right, fill from the left, both towards the
  // viewer's side of the scene.
  const Vec3 key_direction = unit_or(0.8 * camera.right() + 0.9 * camera.up() - 0.45 * camera.forward(), {0, 1, 0});
  const Vec3 fill_direction = unit_or(-0.8 * camera.right() - 0.2 * camera.up() - 0.55 * camera.forward(), {0, 1, 0});

  glViewport(0, 0, width, height);
  const Colour& background = options.background_colour;
  glClearColor(background.r, background.g, background.b, 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  glEnable(GL_MULTISAMPLE);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);

  // Bounding box of the finite positions: ground placement and marker sizes.
  const double inf = std::numeric_limits<double>::infinity();
  Vec3 low{inf, inf, inf};
  Vec3 high{-inf, -inf, -inf};
  for (const Vec3& p : position) {
    if (!is_finite(p)) continue;
    low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
    high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
  }
  const bool any_finite = low.x <= high.x;
  const double spacing = model.spacing > 0.0 ? model.spacing : 1.0;
  const double sheet_size = std::max({spacing * std::max(model.rows, model.cols), any_finite ? high.x - low.x : 0.0,
                                      any_finite ? high.z - low.z : 0.0});

  // --- Ground ---
  const bool floor_drawn =
      options.show_colliders && std::any_of(model.colliders.begin(), model.colliders.end(), is_floor);
  if (options.show_ground && any_finite && !floor_drawn) {
    const double ground_y = options.ground_height ? *options.ground_height : automatic_ground_height(model, position);
    const double extent = options.ground_extent > 0.0 ? options.ground_extent : 1.5 * sheet_size;
    const Vec3 centre{0.5 * (low.x + high.x), ground_y, 0.5 * (low.z + high.z)};
    // Cell: a round number near a tenth of the sheet (1, 2 or 5 times a power of ten).
    const double raw = sheet_size / 10.0;
    const double decade = std::pow(10.0, std::floor(std::log10(raw)));
    const double cell = raw / decade < 1.5 ? decade : (raw / decade < 3.5 ? 2.0 * decade : 5.0 * decade);
    impl.vertex_data.clear();
    for (const auto& corner : {std::array<double, 2>{-1, -1}, {1, -1}, {-1, 1}, {1, 1}}) {
      push_vec3(impl.vertex_data, centre + Vec3{corner[0] * extent, 0.0, corner[1] * extent});
    }
    glUseProgram(impl.ground);
    set_matrix(impl.ground, "view_projection", view_projection);
    set_colour(impl.ground, "ground_colour", options.ground_colour);
    set_vec3(impl.ground, "centre", centre);
    glUniform1f(glGetUniformLocation(impl.ground, "cell"), static_cast<float>(cell));
    glUniform1f(glGetUniformLocation(impl.ground, "extent"), static_cast<float>(extent));
    impl.ground_quad.upload(impl.vertex_data, {0}, 3);
    glEnable(GL_BLEND);
    glDepthMask(GL_FALSE);  // a transparent plane must not hide what is drawn after it
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
  }

  // --- Colliders ---
  if (options.show_colliders && !model.colliders.empty()) {
    const Vec3 focus = any_finite ? 0.5 * (low + high) : Vec3{};
    // Planes first, in the ground's colour (they are floors and walls, and a box standing on a
    // floor of its own colour would not stand out), then the bounded shapes.
    impl.vertex_data.clear();
    for (const bool planes : {true, false}) {
      for (const Collider& collider : model.colliders) {
        if ((collider.shape == ColliderShape::plane) != planes) continue;
        const Vec3 shift = collider.path.position(time) - collider.path.position(0.0);
        append_collider(collider, shift, focus, 1.5 * sheet_size, impl.vertex_data);
      }
      if (planes) impl.plane_vertex_count = static_cast<GLsizei>(impl.vertex_data.size() / 6);
    }
    const auto vertex_count = static_cast<GLsizei>(impl.vertex_data.size() / 6);
    impl.colliders.upload(impl.vertex_data, {0, 3}, 6);
    glUseProgram(impl.lit_sheet);
    set_matrix(impl.lit_sheet, "view_projection", view_projection);
    set_vec3(impl.lit_sheet, "eye", eye);
    set_vec3(impl.lit_sheet, "key_direction", key_direction);
    set_vec3(impl.lit_sheet, "fill_direction", fill_direction);
    glUniform1f(glGetUniformLocation(impl.lit_sheet, "opacity"), 1.0f);
    for (const Colour* colour : {&options.ground_colour, &options.collider_colour}) {
      const bool planes = colour == &options.ground_colour;
      const GLsizei first = planes ? 0 : impl.plane_vertex_count;
      const GLsizei count = planes ? impl.plane_vertex_count : vertex_count - impl.plane_vertex_count;
      if (count == 0) continue;
      set_colour(impl.lit_sheet, "front_colour", *colour);
      set_colour(impl.lit_sheet, "back_colour", *colour);
      glDrawArrays(GL_TRIANGLES, first, count);
    }
  }

  // --- Sheet ---
  build_sheet_mesh(model, position, options.mesh_mode, impl.mesh);
  const SheetMesh& mesh = impl.mesh;
  if (!mesh.triangle_vertices.empty() && (options.show_sheet || options.show_wireframe)) {
    impl.vertex_data.clear();
    impl.vertex_data.reserve(mesh.vertex_position.size() * 6);
    for (std::size_t v = 0; v < mesh.vertex_position.size(); ++v) {
      push_vec3(impl.vertex_data, mesh.vertex_position[v]);
      push_vec3(impl.vertex_data, mesh.vertex_normal[v]);
    }
    impl.sheet.upload(impl.vertex_data, {0, 3}, 6);
    if (mesh.topology_version != impl.uploaded_topology) {
      impl.sheet.upload_elements(mesh.triangle_vertices.data(),
                                 mesh.triangle_vertices.size() * sizeof(mesh.triangle_vertices[0]));
      impl.uploaded_topology = mesh.topology_version;
    }
    const auto index_count = static_cast<GLsizei>(mesh.triangle_vertices.size() * 3);
    glBindVertexArray(impl.sheet.array);
    if (options.show_sheet) {
      glUseProgram(impl.lit_sheet);
      set_matrix(impl.lit_sheet, "view_projection", view_projection);
      set_colour(impl.lit_sheet, "front_colour", options.front_colour);
      set_colour(impl.lit_sheet, "back_colour", options.back_colour);
      set_vec3(impl.lit_sheet, "eye", eye);
      set_vec3(impl.lit_sheet, "key_direction", key_direction);
      set_vec3(impl.lit_sheet, "fill_direction", fill_direction);
      glUniform1f(glGetUniformLocation(impl.lit_sheet, "opacity"), 1.0f);
      glEnable(GL_POLYGON_OFFSET_FILL);
      glPolygonOffset(1.0f, 1.0f);
      glDrawElements(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, nullptr);
      glDisable(GL_POLYGON_OFFSET_FILL);
    }
    if (options.show_wireframe) {
      glUseProgram(impl.flat_line);
      set_matrix(impl.flat_line, "view_projection", view_projection);
      set_colour(impl.flat_line, "line_colour", options.wireframe_colour);
      glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
      glDrawElements(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, nullptr);
      glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    }
  }

  // --- Springs ---
  if (options.show_connectors) {
    impl.line_data.clear();
    // Broken connectors exert no force and are not drawn.
    for (std::size_t e = 0; e < model.connector_count(); ++e) {
      if (model.connector_live[e] == 0) continue;
      const auto [a, b] = model.connector_particles[e];
      push_vec3(impl.line_data, position[a]);
      push_vec3(impl.line_data, position[b]);
    }
    impl.draw_lines(impl.line_data, options.connector_colour, view_projection);
  }
  if (options.show_radials && model.radial_count() > 0) {
    // Normals at the particles orient the half circles of opposite pairs; in particle mode the
    // mesh's first vertices are the particles, torn or not.
    const std::vector<Vec3> particle_normal =
        mesh.vertex_position.size() >= position.size() && options.mesh_mode == SheetMeshMode::particles
            ? std::vector<Vec3>(mesh.vertex_normal.begin(),
                                mesh.vertex_normal.begin() + static_cast<std::ptrdiff_t>(position.size()))
            : vertex_normals(model, position, lattice_triangles(model));
    impl.line_data.clear();
    for (std::size_t r = 0; r < model.radial_count(); ++r) {
      if (model.radial_live[r] == 0) continue;
      const auto [centre_index, b, c] = model.radial_particles[r];
      const Vec3& centre = position[centre_index];
      const Vec3 to_b = unit_or(position[b] - centre, {1, 0, 0});
      const Vec3 to_c = unit_or(position[c] - centre, {0, 0, 1});
      const bool opposite = model.radial_kind[r] == RadialKind::opposite;
      const double radius = (opposite ? 0.4 : 0.25) * spacing;
      // The arc runs from to_b towards `side` through the angle `sweep`, in the plane (to_b, side).
      double sweep = std::atan2(norm(cross(to_b, to_c)), dot(to_b, to_c));
      Vec3 side = to_c - dot(to_c, to_b) * to_b;
      if (opposite) {
        sweep = kPi;
        side = particle_normal[centre_index] - dot(particle_normal[centre_index], to_b) * to_b;
      }
      side = unit_or(side, unit_or(cross(to_b, Vec3{0, 1, 0}), {0, 0, 1}));
      Vec3 previous = centre + radius * to_b;
      for (int s = 1; s <= kArcSegments; ++s) {
        const double angle = sweep * s / kArcSegments;
        const Vec3 next = centre + radius * (std::cos(angle) * to_b + std::sin(angle) * side);
        push_vec3(impl.line_data, previous);
        push_vec3(impl.line_data, next);
        previous = next;
      }
    }
    impl.draw_lines(impl.line_data, options.radial_colour, view_projection);
  }

  // --- Anchors and the highlighted particle ---
  // Radius: 0.45 L, but never below 5 pixels at the target's distance, so a marker on a large
  // sheet seen from far away is still visible.
  const double pixel = 2.0 * camera.distance * std::tan(camera.field_of_view / 2.0) / height;
  const double radius = options.anchor_radius > 0.0 ? options.anchor_radius : std::max(0.45 * spacing, 5.0 * pixel);
  auto draw_spheres = [&](const std::vector<float>& centres, const Colour& colour, double sphere_radius) {
    if (centres.empty()) return;
    glUseProgram(impl.lit_sphere);
    set_matrix(impl.lit_sphere, "view_projection", view_projection);
    set_colour(impl.lit_sphere, "front_colour", colour);
    set_colour(impl.lit_sphere, "back_colour", colour);
    set_vec3(impl.lit_sphere, "eye", eye);
    set_vec3(impl.lit_sphere, "key_direction", key_direction);
    set_vec3(impl.lit_sphere, "fill_direction", fill_direction);
    glUniform1f(glGetUniformLocation(impl.lit_sphere, "radius"), static_cast<float>(sphere_radius));
    glBindVertexArray(impl.sphere.array);
    glBindBuffer(GL_ARRAY_BUFFER, impl.sphere_instances);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(centres.size() * sizeof(float)), centres.data(),
                 GL_STREAM_DRAW);
    const auto instances = static_cast<GLsizei>(centres.size() / 3);
    // Visible parts, opaque.
    glUniform1f(glGetUniformLocation(impl.lit_sphere, "opacity"), 1.0f);
    glDrawElementsInstanced(GL_TRIANGLES, impl.sphere_index_count, GL_UNSIGNED_INT, nullptr, instances);
    // Hidden parts (behind the sheet), see-through, without touching the depth buffer.
    glEnable(GL_BLEND);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_FALSE);
    glUniform1f(glGetUniformLocation(impl.lit_sphere, "opacity"), 0.45f);
    glDrawElementsInstanced(GL_TRIANGLES, impl.sphere_index_count, GL_UNSIGNED_INT, nullptr, instances);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glDisable(GL_BLEND);
  };
  if (options.show_anchors) {
    impl.instance_data.clear();
    for (const Anchor& anchor : model.anchors) {
      if (anchor.particle < position.size()) push_vec3(impl.instance_data, position[anchor.particle]);
    }
    draw_spheres(impl.instance_data, options.anchor_colour, radius);
  }
  if (options.highlighted_particle >= 0 && static_cast<std::size_t>(options.highlighted_particle) < position.size()) {
    impl.instance_data.clear();
    push_vec3(impl.instance_data, position[static_cast<std::size_t>(options.highlighted_particle)]);
    draw_spheres(impl.instance_data, options.highlight_colour, 1.2 * radius);
  }

  glBindVertexArray(0);
  glUseProgram(0);
}

}  // namespace clothsim::render
