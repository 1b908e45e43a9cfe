#version 450
#extension GL_GOOGLE_include_directive : require
// The state of stage i of a Runge-Kutta step (ExplicitRungeKutta::compute_stages on the CPU):
// y_i = y + h sum_{j<i} a_ij (V_j, K_j) in Nystrom form (rows of device_step.h), term by term in
// the CPU's order, zero coefficients skipped; an anchored particle is put on its path at the stage
// time instead (ClothDynamics::constrain). Stage 0 is the state itself. Writes the arrays the
// force passes read: in float32 as offsets from the state's high parts, starting from its low
// parts (stage_offsets.glsl, split_state.glsl).
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/device_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Position { Real position[]; };          // [3 particles], m
layout(std430, binding = 1) readonly buffer Velocity { Real velocity[]; };          // [3 particles], m/s
layout(std430, binding = 2) readonly buffer Acceleration { Real acceleration[]; };  // [stages][3 particles], m/s^2
layout(std430, binding = 3) readonly buffer Rows { Real rows[]; };                  // the method's Nystrom rows
layout(std430, binding = 4) readonly buffer ControlReal { Real control_real[]; };
layout(std430, binding = 5) readonly buffer ControlUint { uint control_uint[]; };
layout(std430, binding = 6) readonly buffer ParticleAnchor { int particle_anchor[]; };  // anchor row, or -1
layout(std430, binding = 7) readonly buffer AnchorPaths { Real anchor_paths[]; };
layout(std430, binding = 8) writeonly buffer StagePosition { Real stage_position[]; };
layout(std430, binding = 9) writeonly buffer StageVelocity { Real stage_velocity[]; };
layout(std430, binding = 10) readonly buffer PositionLow { Real position_low[]; };  // float32: the state's low parts
layout(std430, binding = 11) readonly buffer VelocityLow { Real velocity_low[]; };

layout(push_constant) uniform Constants { StagePassConstants constants; };

#include "gpu/shaders/anchor_motion.glsl"

Vec3 load(uint array, uint p) {
  if (array == 0u) return Vec3(position[3 * p], position[3 * p + 1], position[3 * p + 2]);
  return Vec3(velocity[3 * p], velocity[3 * p + 1], velocity[3 * p + 2]);
}

Vec3 load_low(uint array, uint p) {
  if (array == 0u) return Vec3(position_low[3 * p], position_low[3 * p + 1], position_low[3 * p + 2]);
  return Vec3(velocity_low[3 * p], velocity_low[3 * p + 1], velocity_low[3 * p + 2]);
}

Vec3 stage_acceleration(uint l, uint p) {
  const uint base = 3 * (l * constants.particle_count + p);
  return Vec3(acceleration[base], acceleration[base + 1], acceleration[base + 2]);
}

void main() {
  const uint p = invocation_index();
  if (p >= constants.particle_count || control_uint[kActive] == 0u) return;
  const Real h = control_real[kStep];
  const uint row = constants.stage * kRowReals;
  Vec3 x;
  Vec3 v;
  const int anchor = particle_anchor[p];
  if (anchor >= 0) {
    // The stage's node c_i is the sum of its row's weights.
    const PathMotion motion = anchor_motion(uint(anchor), control_real[kElapsed] + rows[row] * h);
    x = motion.position;
    v = motion.velocity;
#if CLOTHSIM_STAGE_OFFSETS
    x = (x - load(0u, p)) - load_low(0u, p);
    v = (v - load(1u, p)) - load_low(1u, p);
#endif
  } else {
    const Vec3 v0 = load(1u, p);
#if CLOTHSIM_STAGE_OFFSETS
    x = load_low(0u, p);
    v = load_low(1u, p);
    if (rows[row] != Real(0.0)) x += (h * rows[row]) * v0 + (h * rows[row]) * v;
#else
    x = load(0u, p);
    v = v0;
    if (rows[row] != Real(0.0)) x += (h * rows[row]) * v0;
#endif
    for (uint l = 0u; l < constants.stage; ++l) {
      const Real position_weight = rows[row + 1u + l];
      const Real velocity_weight = rows[row + 1u + kMaxDeviceStages + l];
      if (position_weight == Real(0.0) && velocity_weight == Real(0.0)) continue;
      const Vec3 k = stage_acceleration(l, p);
      if (position_weight != Real(0.0)) x += (h * h * position_weight) * k;
      if (velocity_weight != Real(0.0)) v += (h * velocity_weight) * k;
    }
  }
  stage_position[3 * p] = x.x;
  stage_position[3 * p + 1] = x.y;
  stage_position[3 * p + 2] = x.z;
  stage_velocity[3 * p] = v.x;
  stage_velocity[3 * p + 1] = v.y;
  stage_velocity[3 * p + 2] = v.z;
}
