#version 450
#extension GL_GOOGLE_include_directive : require
// Implicit Euler's block Jacobi preconditioner on the device: one invocation per particle sums the
// diagonal blocks of its elements' k_s K + d_s C (implicit_factors.glsl) in the gather table's
// order, adds its mass and drag, and stores the block's inverse (BlockSystem::assemble's
// `preconditioner`); zero where anchored.
#include "gpu/shaders/element_jacobian.glsl"
#include "gpu/shaders/implicit_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer GatherOffset { uint gather_offset[]; };
layout(std430, binding = 1) readonly buffer GatherSlot { uint gather_slot[]; };
layout(std430, binding = 2) readonly buffer ConnectorFactors { Real connector_factors[]; };
layout(std430, binding = 3) readonly buffer RadialFactors { Real radial_factors[]; };
layout(std430, binding = 4) readonly buffer Mass { Real particle_mass[]; };
layout(std430, binding = 5) readonly buffer Environment { Real environment[]; };
layout(std430, binding = 6) readonly buffer ParticleAnchor { int particle_anchor[]; };
layout(std430, binding = 7) readonly buffer SolveReal { Real solve_real[]; };
layout(std430, binding = 8) writeonly buffer Jacobi { Real jacobi[]; };  // [particle_count][9], column by column

layout(push_constant) uniform Constants { ImplicitPassConstants constants; };

#include "gpu/shaders/implicit_factors.glsl"

void main() {
  const uint p = invocation_index();
  if (p >= constants.particle_count) return;
  Mat3 inverse_block = Mat3(0.0);
  if (particle_anchor[p] < 0) {
    const Real stiffness_scale = solve_real[kStiffnessScale];
    const Real damping_scale = solve_real[kDampingScale];
    Mat3 block = Mat3(0.0);
    for (uint k = gather_offset[p]; k < gather_offset[p + 1]; ++k) {
      const uint slot = gather_slot[k];
      if (slot < constants.radial_slot_base) {
        block += connector_diagonal(load_connector(slot / 2u), stiffness_scale, damping_scale);
      } else {
        const uint local = slot - constants.radial_slot_base;
        block += radial_diagonal(load_radial(local / 3u), local % 3u, stiffness_scale, damping_scale);
      }
    }
    block += (particle_mass[p] + damping_scale * environment[3]) * Mat3(1.0);
    inverse_block = inverse(block);
  }
  for (uint column = 0u; column < 3u; ++column) {
    for (uint row = 0u; row < 3u; ++row) jacobi[9 * p + 3 * column + row] = inverse_block[column][row];
  }
}
