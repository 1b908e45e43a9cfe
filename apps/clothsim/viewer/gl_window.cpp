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

#if defined(CLOTHSIM_SANITIZE)
#include <dlfcn.h>
#include <link.h>
#endif

#include "render/renderer.h"

namespace clothsim::viewer {
namespace {

std::string g_glfw_error;  // the last GLFW error, for messages

void on_glfw_error(int /*code*/, const char* description) { g_glfw_error = description; }

#if defined(CLOTHSIM_SANITIZE)
// Sanitizer builds only (docs/testing.md, "The sanitizer suite"): keeps Mesa's DRI driver loaded
// until the process exits. GLX unloads it when the window's display closes, before LeakSanitizer
// looks at the heap at exit; the blocks the driver's static data still pointed to then look
// leaked (240 bytes, allocated in "<unknown module>", which no suppression can name). Loaded,
// they are reachable, as they are in any process that keeps its driver.
void keep_gl_driver_loaded() {
  std::vector<std::string> drivers;
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* found) {
        const std::string_view name = info->dlpi_name != nullptr ? info->dlpi_name : "";
        if (name.ends_with("_dri.so")) static_cast<std::vector<std::string>*>(found)->emplace_back(name);
        return 0;
      },
      &drivers);
  for (const std::string& driver : drivers) dlopen(driver.c_str(), RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
}
#endif

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
  keep_gl_driver_loaded();
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
