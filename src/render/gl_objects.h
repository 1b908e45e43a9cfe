// The renderer's OpenGL plumbing: shader programs compiled and linked with the driver's log in
// the error, uniforms set by name, and a vertex array with its buffers. All of it needs a current
// OpenGL 3.3 core context (renderer.h); entry points come from libepoxy.
#pragma once

#include <epoxy/gl.h>

#include <cstddef>
#include <initializer_list>
#include <vector>

#include "core/vec3.h"
#include "render/camera.h"
#include "render/render_options.h"

namespace clothsim::render {

// A program of a vertex and a fragment shader; `name` says which in messages. Throws RenderError
// with the driver's log when either does not compile or the program does not link.
GLuint link_program(const char* vertex, const char* fragment, const char* name);

// Uniforms of the program in use, by name: an sRGB colour, a vector (as floats), a matrix.
void set_colour(GLuint program, const char* name, const Colour& colour);
void set_vec3(GLuint program, const char* name, const Vec3& v);
void set_matrix(GLuint program, const char* name, const Mat4& matrix);

// A vertex array with one float buffer of vec3 attributes at locations 0.. and an optional
// element buffer. Plain handles: create() and destroy() are called by the owner, whose context
// must be current.
struct Buffers {
  GLuint array = 0;
  GLuint vertices = 0;
  GLuint elements = 0;

  void create();
  void destroy();
  // Uploads `data` (orphaning the old storage) and declares vec3 attributes at the given offsets
  // (in floats) of each `stride_floats`-float vertex.
  void upload(const std::vector<float>& data, std::initializer_list<int> attribute_offsets, int stride_floats);
  // Uploads the element buffer (GL_STATIC_DRAW: indices change only with the mesh's topology).
  void upload_elements(const void* data, std::size_t bytes);
};

}  // namespace clothsim::render
