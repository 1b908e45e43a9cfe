#version 450
#extension GL_GOOGLE_include_directive : require
// An accepted step on the device (ExplicitRungeKutta::accept and combine_solution's work
// integrals on the CPU): when rk_control accepted the attempt, each particle takes its trial
// state (in float32 its low parts too: split_state.glsl), and each particle and element its share
// of the step's work, h sum_i b_i P_i (damping power per element, or per particle on the lattice
// path; drag and anchor power per particle, those two and the lattice path's damping power summed
// over the stages already), summed per workgroup in shared memory for rk_control's phase 1.
// Invocations cover max(particles, elements).
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/device_step.h"

const uint kWorkgroupSize = kReduceWorkgroup;
layout(local_size_x = kWorkgroupSize) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer ControlReal { Real control_real[]; };
layout(std430, binding = 1) readonly buffer ControlUint { uint control_uint[]; };
layout(std430, binding = 2) readonly buffer TrialPosition { Real trial_position[]; };
layout(std430, binding = 3) readonly buffer TrialVelocity { Real trial_velocity[]; };
layout(std430, binding = 4) writeonly buffer Position { Real position[]; };
layout(std430, binding = 5) writeonly buffer Velocity { Real velocity[]; };
layout(std430, binding = 6) readonly buffer ElementPower { Real element_power[]; };    // [stages][elements], W
layout(std430, binding = 7) readonly buffer ParticlePower { Real particle_power[]; };  // [3][particles], W, weighed
layout(std430, binding = 8) readonly buffer Rows { Real rows[]; };
layout(std430, binding = 9) writeonly buffer BlockWork { Real block_work[]; };  // [blocks][3], J
layout(std430, binding = 10) readonly buffer TrialPositionLow { Real trial_position_low[]; };  // float32
layout(std430, binding = 11) readonly buffer TrialVelocityLow { Real trial_velocity_low[]; };
layout(std430, binding = 12) writeonly buffer PositionLow { Real position_low[]; };
layout(std430, binding = 13) writeonly buffer VelocityLow { Real velocity_low[]; };

layout(push_constant) uniform Constants { AcceptPassConstants constants; };

#include "gpu/shaders/workgroup_sums.glsl"


void main() {
  if (control_uint[kAccepted] == 0u) return;  // the same for the whole dispatch
  const uint index = invocation_index();
  const uint n = constants.particle_count;
  const uint elements = constants.element_count;
  const uint weights = solution_weight_slot(constants.stages, 0u);  // the row b's velocity weights
  Real damping = Real(0.0);
  Real drag = Real(0.0);
  Real anchor = Real(0.0);
  if (index < n) {
    for (uint k = 0u; k < 3u; ++k) {
      position[3 * index + k] = trial_position[3 * index + k];
      velocity[3 * index + k] = trial_velocity[3 * index + k];
#if CLOTHSIM_STAGE_OFFSETS
      position_low[3 * index + k] = trial_position_low[3 * index + k];
      velocity_low[3 * index + k] = trial_velocity_low[3 * index + k];
#endif
    }
    // Summed over the stages already, weighed by the solution row (device_step.h).
    drag = particle_power[index];
    anchor = particle_power[n + index];
    if (constants.particle_damping != 0u) damping = particle_power[2 * n + index];
  }
  if (index < elements) {
    for (uint l = 0u; l < constants.stages; ++l) damping += rows[weights + l] * element_power[l * elements + index];
  }
  const Real h = control_real[kTakenStep];
  Real works[3] = Real[3](h * damping, h * drag, h * anchor);
  sum_over_workgroup(works);
  const uint group = workgroup_index();
  if (gl_LocalInvocationID.x == 0u && group < constants.blocks) {
    for (uint k = 0u; k < 3u; ++k) block_work[3 * group + k] = workgroup_sum[k][0];
  }
}
