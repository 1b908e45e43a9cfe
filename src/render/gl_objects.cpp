// OpenGL programs, uniforms and buffers (gl_objects.h).
#include "render/gl_objects.h"

#include <array>
#include <cstdint>
#include <string>

#include "render/render_error.h"

namespace clothsim::render {
namespace {

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

}  // namespace

GLuint link_program(const char* vertex, const char* fragment, const char* name) {
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

void Buffers::create() {
  glGenVertexArrays(1, &array);
  glGenBuffers(1, &vertices);
  glGenBuffers(1, &elements);
}

void Buffers::destroy() {
  glDeleteBuffers(1, &elements);
  glDeleteBuffers(1, &vertices);
  glDeleteVertexArrays(1, &array);
}

void Buffers::upload(const std::vector<float>& data, std::initializer_list<int> attribute_offsets, int stride_floats) {
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

void Buffers::upload_elements(const void* data, std::size_t bytes) {
  glBindVertexArray(array);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, elements);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(bytes), data, GL_STATIC_DRAW);
}

}  // namespace clothsim::render
