// The compute shaders, compiled from src/gpu/shaders/*.comp to SPIR-V by glslc at build time and
// compiled into the library as arrays of words (cmake/embed_spirv.cmake writes
// embedded_shaders.cpp in the build folder), so nothing is looked up at run time. Each shader is
// built twice, as "<name>.float32" and "<name>.float64" (CLOTHSIM_FLOAT64 = 0 or 1).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "gpu/device.h"

namespace clothsim::gpu {

// The SPIR-V of shader `name` ("accumulate_connector_springs.float64"); throws GpuError for a
// name that was not built.
std::span<const std::uint32_t> embedded_shader(std::string_view name);

// "<name>.float32" or "<name>.float64".
inline std::string shader_variant(std::string_view name, Precision precision) {
  return std::string(name) + "." + to_string(precision);
}

}  // namespace clothsim::gpu
