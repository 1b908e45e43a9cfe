// The push constants of the element force passes (accumulate_connector_springs.comp,
// accumulate_radial_springs.comp), one struct read by C++ (src/gpu/element_forces.cpp) and by
// GLSL, so that the two cannot disagree on the layout: 32-bit fields only, offsets 0, 4, ...
#if defined(__cplusplus)
#pragma once
#include <cstdint>
namespace clothsim::gpu {
using uint = std::uint32_t;
#endif

struct ElementPassConstants {
  uint element_count;  // connectors or radial springs in the pass
  uint damped;         // 1: the springs' damping acts; 0: elastic forces only (kSpringDamping off)
};

#if defined(__cplusplus)
}  // namespace clothsim::gpu
#endif
