#version 450
#extension GL_GOOGLE_include_directive : require
// The state of stage i of a Runge-Kutta step (stage_state.glsl), written for the force passes:
// in float32 as offsets from the state's high parts (stage_offsets.glsl, split_state.glsl). The
// lattice path's fused stage pass (lattice_stage) forms the same states where it needs them.
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/device_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Position { Real origin_position[]; };   // the state, [3 particles], m
layout(std430, binding = 1) readonly buffer Velocity { Real origin_velocity[]; };   // [3 particles], m/s
layout(std430, binding = 2) readonly buffer Acceleration { Real acceleration[]; };  // [stages][3 particles], m/s^2
layout(std430, binding = 3) readonly buffer Rows { Real rows[]; };                  // the method's Nystrom rows
layout(std430, binding = 4) readonly buffer ControlReal { Real control_real[]; };
layout(std430, binding = 5) readonly buffer ControlUint { uint control_uint[]; };
layout(std430, binding = 6) readonly buffer ParticleAnchor { int particle_anchor[]; };  // anchor row, or -1
layout(std430, binding = 7) readonly buffer AnchorPaths { Real anchor_paths[]; };
layout(std430, binding = 8) writeonly buffer StagePosition { Real stage_position[]; };
layout(std430, binding = 9) writeonly buffer StageVelocity { Real stage_velocity[]; };
layout(std430, binding = 10) readonly buffer PositionLow { Real origin_position_low[]; };  // float32: the state's low parts
layout(std430, binding = 11) readonly buffer VelocityLow { Real origin_velocity_low[]; };

layout(push_constant) uniform Constants { StagePassConstants constants; };

#include "gpu/shaders/stage_state.glsl"

void main() {
  const uint p = invocation_index();
  if (p >= constants.particle_count || control_uint[kActive] == 0u) return;
  const StagePoint point = stage_state(p, constants.stage);
  stage_position[3 * p] = point.position.x;
  stage_position[3 * p + 1] = point.position.y;
  stage_position[3 * p + 2] = point.position.z;
  stage_velocity[3 * p] = point.velocity.x;
  stage_velocity[3 * p + 1] = point.velocity.y;
  stage_velocity[3 * p + 2] = point.velocity.z;
}
