// The push constants of the force passes (accumulate_connector_springs.comp,
// accumulate_radial_springs.comp, gather_forces.comp, deterministic_sum.comp), structs read by C++ (src/gpu) and by
// GLSL, so that the two cannot disagree on the layout: 32-bit fields only, offsets 0, 4, ...
#if defined(__cplusplus)
#pragma once
#include <cstdint>
namespace clothsim::gpu {
using uint = std::uint32_t;
#define CLOTHSIM_ELEMENT_SLOT inline constexpr uint
#else
#define CLOTHSIM_ELEMENT_SLOT const uint
#endif

// DeviceForces' radial_active: 0 where a radial spring does not act, else its kind.
CLOTHSIM_ELEMENT_SLOT kRadialActiveAdjacent = 1;
CLOTHSIM_ELEMENT_SLOT kRadialActiveOpposite = 2;

struct ElementPassConstants {
  uint element_count;  // connectors or radial springs in the pass
  uint damped;         // 1: the springs' damping acts; 0: elastic forces only (kSpringDamping off)
  uint slot_base;      // the pass's first force slot: 0 for connectors, radial_slot_base() for radials
  uint power_base;     // the pass's first damping power: 0 for connectors, connector_count() for radials
};

struct GatherConstants {
  uint particle_count;
};

struct SumConstants {
  uint count;       // values to add
  uint block_size;  // values per block, added in index order (forces.cpp's kReductionBlock)
  uint phase;       // 0: one invocation per block; 1: one invocation adds the block sums in order
};

#undef CLOTHSIM_ELEMENT_SLOT
#if defined(__cplusplus)
}  // namespace clothsim::gpu
#endif
