#version 450
#extension GL_GOOGLE_include_directive : require
// The element forces of a lattice sheet by particle, without element lists or force slots: the
// device's form of the CPU's structured kernel (forces/lattice_kernel.h). Each particle evaluates
// the springs it owns (lattice_spring_sums.glsl) and writes the sum of their forces on itself,
// their forces on each of its four neighbours (which stage_acceleration gathers), and their damping
// power. The fused stage pass, lattice_stage, does this pass's work and its neighbours' in one.
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/device_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Position { Real position[]; };    // stage state [3 particles], m
layout(std430, binding = 1) readonly buffer Velocity { Real velocity[]; };    // m/s (float32: offsets)
layout(std430, binding = 2) readonly buffer Params { Real lattice_params[]; };  // [particles][kLatticeParams]
layout(std430, binding = 3) writeonly buffer Forces { Real lattice_forces[]; };  // [particles][kLatticeForces]
layout(std430, binding = 4) buffer ParticlePower { Real particle_power[]; };  // [3][particles], W (device_step.h)
layout(std430, binding = 5) readonly buffer ControlUint { uint control_uint[]; };
layout(std430, binding = 6) readonly buffer EventParams { Real event_params[]; };  // [particles][kEventParams]
layout(std430, binding = 7) readonly buffer OriginPosition { Real origin_position[]; };  // the step's start, m
layout(std430, binding = 8) readonly buffer OriginVelocity { Real origin_velocity[]; };  // m/s
layout(std430, binding = 9) readonly buffer Rows { Real rows[]; };  // the method's Nystrom rows

layout(push_constant) uniform Constants { LatticePassConstants constants; };

#include "gpu/shaders/stage_offsets.glsl"
#include "gpu/shaders/lattice_spring_sums.glsl"

void main() {
  const uint p = invocation_index();
  const uint n = constants.particle_count;
  if (p >= n || control_uint[kActive] == 0u) return;
  const LatticeSpringSums sums = particle_spring_sums(p, kEveryArm);
  const uint slot = p * kLatticeForces;
  lattice_forces[slot] = sums.own.x;
  lattice_forces[slot + 1u] = sums.own.y;
  lattice_forces[slot + 2u] = sums.own.z;
  for (uint d = 0u; d < 4u; ++d) {
    lattice_forces[slot + 3u + 3u * d] = sums.to[d].x;
    lattice_forces[slot + 4u + 3u * d] = sums.to[d].y;
    lattice_forces[slot + 5u + 3u * d] = sums.to[d].z;
  }
  // Weighed by the solution row, summed over the stages (device_step.h).
  const Real weight = rows[solution_weight_slot(constants.stages, constants.stage)];
  particle_power[2u * n + p] = (constants.stage == 0u ? Real(0.0) : particle_power[2u * n + p]) + weight * sums.power;
}
