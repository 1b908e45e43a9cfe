// Numbers in diagnoses (a failed simulation's message): six significant digits, enough to tell
// values apart and short enough to read; scene/parameters.h's format_number is the one for values
// that must read back exactly.
#pragma once

#include <cstdio>
#include <string>

#include "core/vec3.h"

namespace clothsim {

inline std::string diagnostic_number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

inline std::string diagnostic_vector(const Vec3& v) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.6g, %.6g, %.6g)", v.x, v.y, v.z);
  return buffer;
}

}  // namespace clothsim
