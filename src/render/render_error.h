// The error type of the render module.
#pragma once

#include <stdexcept>

namespace clothsim::render {

// OpenGL or EGL is missing or too old, a shader failed to compile, ffmpeg could not be run or
// failed. The message says what failed and, where there is one, how to work around it.
class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace clothsim::render
