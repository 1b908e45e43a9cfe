// The GLFW and OpenGL plumbing under the viewer's window (viewer_window.cpp): the library's
// lifetime, opening an OpenGL 3.3 core window, telling a software renderer, and reading the back
// buffer for screenshots. Kept apart so that viewer_window.cpp holds only the viewer's own logic.
#pragma once

#include <string>

#include "render/image.h"
#include "viewer/viewer_window.h"

struct GLFWwindow;

namespace clothsim::viewer {

// glfwInit/glfwTerminate for a scope. Throws render::RenderError, with advice, without a display.
class GlfwLibrary {
 public:
  GlfwLibrary();
  ~GlfwLibrary();
  GlfwLibrary(const GlfwLibrary&) = delete;
  GlfwLibrary& operator=(const GlfwLibrary&) = delete;
};

// An OpenGL 3.3 core window of options' size with `samples` MSAA samples, its context current.
// Throws render::RenderError.
GLFWwindow* open_window(const ViewerOptions& options, const std::string& title, int samples);

// Whether the current context draws on one of Mesa's software rasterisers, which the default of
// 4x MSAA would slow down about five times.
bool is_software_renderer();

// The back buffer, read after the scene is drawn (without the panel), rows top first.
render::Image read_back_buffer(int width, int height);

}  // namespace clothsim::viewer
