#version 450
#extension GL_GOOGLE_include_directive : require
// The trial solution of a step and its error over the particles (rk_trial.glsl), after the stages'
// passes; each workgroup writes its largest error and the first particle that has it, for
// rk_control to reduce. On a lattice with one pass a stage, lattice_stage forms them instead.
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/device_step.h"

const uint kWorkgroupSize = kReduceWorkgroup;
layout(local_size_x = kWorkgroupSize) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Position { Real position[]; };
layout(std430, binding = 1) readonly buffer Velocity { Real velocity[]; };
layout(std430, binding = 2) readonly buffer Acceleration { Real acceleration[]; };  // [stages][3 particles]
layout(std430, binding = 3) readonly buffer Rows { Real rows[]; };
layout(std430, binding = 4) readonly buffer ControlReal { Real control_real[]; };
layout(std430, binding = 5) readonly buffer ControlUint { uint control_uint[]; };
layout(std430, binding = 6) readonly buffer ParticleAnchor { int particle_anchor[]; };
layout(std430, binding = 7) readonly buffer AnchorPaths { Real anchor_paths[]; };
layout(std430, binding = 8) writeonly buffer TrialPosition { Real trial_position[]; };
layout(std430, binding = 9) writeonly buffer TrialVelocity { Real trial_velocity[]; };
layout(std430, binding = 10) writeonly buffer BlockError { Real block_error[]; };
layout(std430, binding = 11) writeonly buffer BlockParticle { uint block_particle[]; };
layout(std430, binding = 12) readonly buffer PositionLow { Real position_low[]; };  // float32: the low parts
layout(std430, binding = 13) readonly buffer VelocityLow { Real velocity_low[]; };
layout(std430, binding = 14) writeonly buffer TrialPositionLow { Real trial_position_low[]; };
layout(std430, binding = 15) buffer TrialVelocityLow { Real trial_velocity_low[]; };

layout(push_constant) uniform Constants { StagePassConstants constants; };  // stage: unused

#include "gpu/shaders/rk_trial.glsl"

void main() {
  if (control_uint[kActive] == 0u) return;  // the same for the whole dispatch
  const uint p = invocation_index();
  Real ratio = Real(0.0);
  if (p < constants.particle_count) {
    StepStart start;
    start.x0 = Vec3(position[3 * p], position[3 * p + 1], position[3 * p + 2]);
    start.v0 = Vec3(velocity[3 * p], velocity[3 * p + 1], velocity[3 * p + 2]);
#if CLOTHSIM_STAGE_OFFSETS
    start.low_x0 = Vec3(position_low[3 * p], position_low[3 * p + 1], position_low[3 * p + 2]);
    start.low_v0 = Vec3(velocity_low[3 * p], velocity_low[3 * p + 1], velocity_low[3 * p + 2]);
#endif
    ratio = trial_and_error(p, constants.symplectic != 0u, start);
  }
  const uint group = workgroup_index();
  reduce_largest_error(ratio, p);
  if (gl_LocalInvocationID.x == 0u && group < (constants.particle_count + kReduceWorkgroup - 1u) / kReduceWorkgroup) {
    block_error[group] = largest_error[0];
    block_particle[group] = largest_particle[0];
  }
}
