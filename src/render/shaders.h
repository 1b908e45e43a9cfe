// The GLSL sources of the renderer (OpenGL 3.3 core), one program per kind of thing drawn:
// the lit surfaces (the sheet, the colliders and, with its own vertex shader, the instanced marker
// spheres), flat lines (springs, wireframe) and the ground grid. renderer.cpp links them; the
// lighting model is in docs/rendering.md.
#pragma once

namespace clothsim::render {

// Shared by the sheet and the spheres: world position and normal in, two-sided shading out.
inline constexpr const char* kLitFragmentShader = R"(#version 330 core
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

inline constexpr const char* kSheetVertexShader = R"(#version 330 core
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

inline constexpr const char* kSphereVertexShader = R"(#version 330 core
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

inline constexpr const char* kLineVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
uniform mat4 view_projection;
void main() { gl_Position = view_projection * vec4(position, 1.0); }
)";

inline constexpr const char* kLineFragmentShader = R"(#version 330 core
out vec4 colour;
uniform vec3 line_colour;  // sRGB
void main() { colour = vec4(line_colour, 1.0); }
)";

inline constexpr const char* kGroundVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
out vec3 world_position;
uniform mat4 view_projection;
void main() {
  world_position = position;
  gl_Position = view_projection * vec4(position, 1.0);
}
)";

inline constexpr const char* kGroundFragmentShader = R"(#version 330 core
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

}  // namespace clothsim::render
