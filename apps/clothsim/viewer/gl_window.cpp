#include "viewer/gl_window.h"

#include <epoxy/gl.h>
// After epoxy: GLFW must not pull in a GL header of its own.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/keep_loaded.h"
#include "render/renderer.h"

namespace clothsim::viewer {
namespace {

std::string g_glfw_error;  // the last GLFW error, for messages

void on_glfw_error(int /*code*/, const char* description) { g_glfw_error = description; }

}  // namespace

GlfwLibrary::GlfwLibrary() {
  glfwSetErrorCallback(on_glfw_error);
  if (glfwInit() != GLFW_TRUE) {
    throw render::RenderError("cannot open a window: " + g_glfw_error +
                              ". 'clothsim view' needs a display (DISPLAY set); on a machine without one, "
                              "run it under a virtual X server: xvfb-run -a clothsim view ...");
  }
}

GlfwLibrary::~GlfwLibrary() { glfwTerminate(); }

GLFWwindow* open_window(const ViewerOptions& options, const std::string& title, int samples) {
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, samples);
  GLFWwindow* window = glfwCreateWindow(options.width, options.height, title.c_str(), nullptr, nullptr);
  if (window == nullptr) throw render::RenderError("cannot open an OpenGL 3.3 core window: " + g_glfw_error);
  glfwMakeContextCurrent(window);
#if defined(CLOTHSIM_SANITIZE)
  // GLX unloads Mesa's DRI driver when the display closes, before LeakSanitizer's check at exit.
  keep_libraries_loaded([](std::string_view path) { return path.ends_with("_dri.so"); });
#endif
  return window;
}

bool is_software_renderer() {
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const std::string name = renderer != nullptr ? renderer : "";
  return name.find("llvmpipe") != std::string::npos || name.find("softpipe") != std::string::npos ||
         name.find("swrast") != std::string::npos;
}

render::Image read_back_buffer(int width, int height) {
  render::Image image;
  image.width = width;
  image.height = height;
  const std::size_t row_bytes = static_cast<std::size_t>(width) * 3;
  std::vector<std::uint8_t> bottom_up(row_bytes * static_cast<std::size_t>(height));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, bottom_up.data());
  image.rgb.resize(bottom_up.size());
  for (int y = 0; y < height; ++y) {
    std::copy_n(&bottom_up[static_cast<std::size_t>(height - 1 - y) * row_bytes], row_bytes,
                &image.rgb[static_cast<std::size_t>(y) * row_bytes]);
  }
  return image;
}

}  // namespace clothsim::viewer
