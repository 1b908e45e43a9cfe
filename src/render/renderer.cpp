// The OpenGL 3.3 core renderer; what it draws and why is in docs/rendering.md.
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
#include <string>
#include <vector>

#include "model/collider.h"
#include "model/sheet_mesh.h"

namespace clothsim::render {
namespace {

constexpr int kArcSegments = 6;
constexpr double kPi = 3.14159265358979323846;

// --- Shaders ---

// Shared by the sheet and the spheres: world position and normal in, two-sided shading out.
constexpr const char* kLitFragmentShader = R"(#version 330 core
in vec3 world_position;
in vec3 world_normal;
out vec4 colour;
uniform vec3 front_colour;   // sRGB
uniform vec3 back_colour;    // sRGB
uniform vec3 eye;
uniform vec3 key_direction;  // unit, towards the light
uniform vec3 fill_direction;
uniform float opacity;

vec3 to_linear(vec3 c) { return pow(c, vec3(2.2)); }
vec3 to_srgb(vec3 c) { return pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)); }

void main() {
  vec3 n = normalize(world_normal);
  vec3 base = to_linear(front_colour);
  if (!gl_FrontFacing) {
    n = -n;
    base = to_linear(back_colour);
  }
  vec3 v = normalize(eye - world_position);
  // Hemisphere ambient: a little more from the sky than from the ground.
  float ambient = mix(0.06, 0.14, 0.5 + 0.5 * n.y);
  float key = max(dot(n, key_direction), 0.0);
  float fill = 0.35 * max(dot(n, fill_direction), 0.0);
  vec3 h = normalize(key_direction + v);
  float specular = key > 0.0 ? 0.25 * pow(max(dot(n, h), 0.0), 48.0) : 0.0;
  vec3 lit = base * (ambient + 0.9 * key + fill) + vec3(specular);
  colour = vec4(to_srgb(lit), opacity);
}
)";

constexpr const char* kSheetVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
out vec3 world_position;
out vec3 world_normal;
uniform mat4 view_projection;
void main() {
  world_position = position;
  world_normal = normal;
  gl_Position = view_projection * vec4(position, 1.0);
}
)";

constexpr const char* kSphereVertexShader = R"(#version 330 core
layout(location = 0) in vec3 unit_position;  // on the unit sphere; also the normal
layout(location = 1) in vec3 centre;         // per instance
out vec3 world_position;
out vec3 world_normal;
uniform mat4 view_projection;
uniform float radius;
void main() {
  world_position = centre + radius * unit_position;
  world_normal = unit_position;
  gl_Position = view_projection * vec4(world_position, 1.0);
}
)";

constexpr const char* kLineVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
uniform mat4 view_projection;
void main() { gl_Position = view_projection * vec4(position, 1.0); }
)";

constexpr const char* kLineFragmentShader = R"(#version 330 core
out vec4 colour;
uniform vec3 line_colour;  // sRGB
void main() { colour = vec4(line_colour, 1.0); }
)";

constexpr const char* kGroundVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
out vec3 world_position;
uniform mat4 view_projection;
void main() {
  world_position = position;
  gl_Position = view_projection * vec4(position, 1.0);
}
)";

constexpr const char* kGroundFragmentShader = R"(#version 330 core
in vec3 world_position;
out vec4 colour;
uniform vec3 ground_colour;      // sRGB
uniform vec3 centre;             // grid centre on the plane
uniform float cell;              // grid cell size, m
uniform float extent;            // fade-out radius, m
void main() {
  vec2 p = (world_position.xz - centre.xz) / cell;
  // Distance to the nearest grid line in pixels, from the screen-space rate of change of p.
  vec2 width = fwidth(p);
  vec2 to_line = abs(fract(p - 0.5) - 0.5) / max(width, vec2(1e-6));
  float line = 1.0 - min(min(to_line.x, to_line.y), 1.0);
  // Every fifth line is a major line.
  vec2 p5 = p / 5.0;
  vec2 to_major = abs(fract(p5 - 0.5) - 0.5) / max(fwidth(p5), vec2(1e-6));
  float major = 1.0 - min(min(to_major.x, to_major.y), 1.0);
  float fade = 1.0 - smoothstep(0.55 * extent, extent, length(world_position.xz - centre.xz));
  float alpha = (0.08 + 0.22 * line + 0.25 * major) * fade;
  colour = vec4(ground_colour * (1.0 - 0.35 * max(line, major)), alpha);
}
)";

GLuint compile(GLenum stage, const char* source, const char* name) {
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    throw RenderError(std::string("the ") + name + " shader does not compile on this OpenGL driver: " + log);
  }
  return shader;
}

GLuint link(const char* vertex, const char* fragment, const char* name) {
  const GLuint vertex_shader = compile(GL_VERTEX_SHADER, vertex, name);
  GLuint fragment_shader = 0;
  try {
    fragment_shader = compile(GL_FRAGMENT_SHADER, fragment, name);
  } catch (...) {
    glDeleteShader(vertex_shader);
    throw;
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, vertex_shader);
  glAttachShader(program, fragment_shader);
  glLinkProgram(program);
  glDeleteShader(vertex_shader);
  glDeleteShader(fragment_shader);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[4096] = {};
    glGetProgramInfoLog(program, sizeof log, nullptr, log);
    glDeleteProgram(program);
    throw RenderError(std::string("the ") + name + " shader program does not link on this OpenGL driver: " + log);
  }
  return program;
}

void set_colour(GLuint program, const char* name, const Colour& colour) {
  glUniform3f(glGetUniformLocation(program, name), colour.r, colour.g, colour.b);
}

void set_vec3(GLuint program, const char* name, const Vec3& v) {
  glUniform3f(glGetUniformLocation(program, name), static_cast<float>(v.x), static_cast<float>(v.y),
              static_cast<float>(v.z));
}

void set_matrix(GLuint program, const char* name, const Mat4& matrix) {
  const std::array<float, 16> values = matrix.to_float();
  glUniformMatrix4fv(glGetUniformLocation(program, name), 1, GL_FALSE, values.data());
}

void push(std::vector<float>& out, const Vec3& v) {
  out.push_back(static_cast<float>(v.x));
  out.push_back(static_cast<float>(v.y));
  out.push_back(static_cast<float>(v.z));
}

Vec3 unit_or(const Vec3& v, const Vec3& fallback) {
  const double length = norm(v);
  return length > 1e-12 && std::isfinite(length) ? v / length : fallback;
}

// A vertex array with one float buffer of `components`-float attributes at locations 0.. and an
// optional element buffer.
struct Buffers {
  GLuint array = 0;
  GLuint vertices = 0;
  GLuint elements = 0;

  void create() {
    glGenVertexArrays(1, &array);
    glGenBuffers(1, &vertices);
    glGenBuffers(1, &elements);
  }
  void destroy() {
    glDeleteBuffers(1, &elements);
    glDeleteBuffers(1, &vertices);
    glDeleteVertexArrays(1, &array);
  }
  // Uploads `data` (orphaning the old storage) and declares vec3 attributes at the given offsets.
  void upload(const std::vector<float>& data, std::initializer_list<int> attribute_offsets, int stride_floats) {
    glBindVertexArray(array);
    glBindBuffer(GL_ARRAY_BUFFER, vertices);
    // glBufferData with new contents gives the buffer new storage (orphaning): the driver need
    // not wait for draws still reading the previous frame's data.
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(float)), data.data(), GL_STREAM_DRAW);
    GLuint location = 0;
    for (const int offset : attribute_offsets) {
      glEnableVertexAttribArray(location);
      glVertexAttribPointer(location, 3, GL_FLOAT, GL_FALSE, stride_floats * static_cast<GLsizei>(sizeof(float)),
                            reinterpret_cast<const void*>(static_cast<std::uintptr_t>(offset) * sizeof(float)));
      ++location;
    }
  }
  void upload_elements(const void* data, std::size_t bytes) {
    glBindVertexArray(array);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, elements);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(bytes), data, GL_STATIC_DRAW);
  }
};

// A UV sphere of unit radius: positions (= normals) and triangle indices.
void make_sphere(int slices, int stacks, std::vector<float>& vertices, std::vector<std::uint32_t>& indices) {
  for (int i = 0; i <= stacks; ++i) {
    const double polar = kPi * i / stacks;
    for (int j = 0; j <= slices; ++j) {
      const double around = 2.0 * kPi * j / slices;
      push(vertices, Vec3{std::sin(polar) * std::cos(around), std::cos(polar), std::sin(polar) * std::sin(around)});
    }
  }
  const auto index = [slices](int i, int j) { return static_cast<std::uint32_t>(i * (slices + 1) + j); };
  for (int i = 0; i < stacks; ++i) {
    for (int j = 0; j < slices; ++j) {
      // Counter-clockwise seen from outside, so gl_FrontFacing holds on the visible side.
      indices.insert(indices.end(), {index(i, j), index(i, j + 1), index(i + 1, j)});
      indices.insert(indices.end(), {index(i, j + 1), index(i + 1, j + 1), index(i + 1, j)});
    }
  }
}

// Collider triangles: position and normal per vertex (6 floats), three vertices per triangle,
// counter-clockwise seen from outside. Shapes are tessellated finely enough that a sphere of a
// third of the picture looks round (48 x 24); this runs per frame, but for a few colliders it is
// far below the sheet's cost.
struct ColliderTriangles {
  std::vector<float>& out;
  void vertex(const Vec3& position, const Vec3& normal) {
    push(out, position);
    push(out, normal);
  }
  void flat(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 normal = unit_or(cross(b - a, c - a), {0, 1, 0});
    vertex(a, normal);
    vertex(b, normal);
    vertex(c, normal);
  }
  // A sphere of `radius` around the segment from `bottom` to `top` along the unit `axis`, with
  // `side` and `front` completing a right-handed frame (side x front = axis; perpendicular_frame()),
  // which makes the triangles below counter-clockwise from outside: the upper hemisphere at `top`, the lower at
  // `bottom`, and the cylinder between them (a sphere when top == bottom).
  void capsule(const Vec3& bottom, const Vec3& top, double radius, const Vec3& axis, const Vec3& side,
               const Vec3& front) {
    constexpr int kSlices = 48;
    constexpr int kStacks = 24;  // even: the equator is a ring, drawn once at each end
    const auto point = [&](int ring, int slice) {
      // Rings 0..kStacks/2 on the top hemisphere, kStacks/2 + 1..kStacks + 1 on the bottom one
      // (ring kStacks/2 + 1 is the equator again, at the bottom end).
      const int stack = ring <= kStacks / 2 ? ring : ring - 1;
      const double polar = kPi * stack / kStacks;
      const double around = 2.0 * kPi * slice / kSlices;
      const Vec3 normal =
          std::cos(polar) * axis + std::sin(polar) * (std::cos(around) * side + std::sin(around) * front);
      return std::pair{(ring <= kStacks / 2 ? top : bottom) + radius * normal, normal};
    };
    for (int ring = 0; ring <= kStacks; ++ring) {
      for (int slice = 0; slice < kSlices; ++slice) {
        const auto p00 = point(ring, slice), p01 = point(ring, slice + 1);
        const auto p10 = point(ring + 1, slice), p11 = point(ring + 1, slice + 1);
        for (const auto& [position, normal] : {p00, p10, p01, p01, p10, p11}) vertex(position, normal);
      }
    }
  }
};

// The frame of a unit axis: two unit vectors perpendicular to it and to each other.
std::pair<Vec3, Vec3> perpendicular_frame(const Vec3& axis) {
  const Vec3 helper = std::abs(axis.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
  const Vec3 side = unit_or(cross(helper, axis), {1, 0, 0});
  return {side, cross(axis, side)};
}

// Appends the triangles of `collider` translated by `shift`. Planes become a square of half-width
// `plane_extent` centred on the point of the plane nearest `focus` (the sheet's centre).
void append_collider(const Collider& collider, const Vec3& shift, const Vec3& focus, double plane_extent,
                     std::vector<float>& out) {
  ColliderTriangles triangles{out};
  switch (collider.shape) {
    case ColliderShape::plane: {
      const Vec3 normal = unit_or(collider.normal, {0, 1, 0});
      const Vec3 point = collider.point + shift;
      const Vec3 centre = focus - dot(focus - point, normal) * normal;
      const auto [u, v] = perpendicular_frame(normal);
      const Vec3 a = centre + plane_extent * (-u - v), b = centre + plane_extent * (u - v);
      const Vec3 c = centre + plane_extent * (u + v), d = centre + plane_extent * (-u + v);
      for (const Vec3& p : {a, b, c, a, c, d}) triangles.vertex(p, normal);
      break;
    }
    case ColliderShape::sphere: {
      const Vec3 centre = collider.center + shift;
      const auto [side, front] = perpendicular_frame({0, 1, 0});
      triangles.capsule(centre, centre, collider.radius, {0, 1, 0}, side, front);
      break;
    }
    case ColliderShape::capsule: {
      const Vec3 axis = unit_or(collider.b - collider.a, {0, 1, 0});
      const auto [side, front] = perpendicular_frame(axis);
      triangles.capsule(collider.a + shift, collider.b + shift, collider.radius, axis, side, front);
      break;
    }
    case ColliderShape::box: {
      const Vec3 centre = collider.center + shift;
      const Vec3& h = collider.half_extents;
      const auto corner = [&](int i) {
        return centre + Vec3{(i & 1 ? 1 : -1) * h.x, (i & 2 ? 1 : -1) * h.y, (i & 4 ? 1 : -1) * h.z};
      };
      // Each face's corners counter-clockwise seen from outside (bit 0: +x, bit 1: +y, bit 2: +z).
      constexpr std::array<std::array<int, 4>, 6> kFaces = {
          {{1, 3, 7, 5}, {0, 4, 6, 2}, {2, 6, 7, 3}, {0, 1, 5, 4}, {4, 5, 7, 6}, {0, 2, 3, 1}}};
      for (const auto& face : kFaces) {
        triangles.flat(corner(face[0]), corner(face[1]), corner(face[2]));
        triangles.flat(corner(face[0]), corner(face[2]), corner(face[3]));
      }
      break;
    }
    case ColliderShape::mesh:
      if (collider.mesh == nullptr) break;
      for (const auto& [a, b, c] : collider.mesh->triangle) {
        triangles.flat(collider.mesh->vertex[a] + shift, collider.mesh->vertex[b] + shift,
                       collider.mesh->vertex[c] + shift);
      }
      break;
  }
}

// An upward horizontal plane: the floor, drawn instead of the ground grid.
bool is_floor(const Collider& collider) { return collider.shape == ColliderShape::plane && collider.normal.y > 0.999; }

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
  impl.lit_sheet = link(kSheetVertexShader, kLitFragmentShader, "sheet");
  impl.lit_sphere = link(kSphereVertexShader, kLitFragmentShader, "marker");
  impl.flat_line = link(kLineVertexShader, kLineFragmentShader, "line");
  impl.ground = link(kGroundVertexShader, kGroundFragmentShader, "ground");
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
      push(impl.vertex_data, centre + Vec3{corner[0] * extent, 0.0, corner[1] * extent});
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
      push(impl.vertex_data, mesh.vertex_position[v]);
      push(impl.vertex_data, mesh.vertex_normal[v]);
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
      push(impl.line_data, position[a]);
      push(impl.line_data, position[b]);
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
        push(impl.line_data, previous);
        push(impl.line_data, next);
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
      if (anchor.particle < position.size()) push(impl.instance_data, position[anchor.particle]);
    }
    draw_spheres(impl.instance_data, options.anchor_colour, radius);
  }
  if (options.highlighted_particle >= 0 && static_cast<std::size_t>(options.highlighted_particle) < position.size()) {
    impl.instance_data.clear();
    push(impl.instance_data, position[static_cast<std::size_t>(options.highlighted_particle)]);
    draw_spheres(impl.instance_data, options.highlight_colour, 1.2 * radius);
  }

  glBindVertexArray(0);
  glUseProgram(0);
}

}  // namespace clothsim::render
