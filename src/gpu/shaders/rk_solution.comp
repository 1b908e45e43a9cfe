#version 450
#extension GL_GOOGLE_include_directive : require
// The trial solution of a step and its error (ExplicitRungeKutta::combine_solution with an
// error row on the CPU, AdaptiveRungeKutta::solution_and_error). Each particle forms y + h sum b_i (V_i, K_i) (or
// symplectic Euler's v + h K_0, x + h v_new), an anchored one its path's state at the step's end,
// and, under error control, its scaled error max_k |e_k| / (atol + rtol max(|y_k|, |y_new,k|))
// with e = h sum (b_i - b^_i) (V_i, K_i); without it, 0. A non-finite trial or error counts as
// kHugeError. Each workgroup writes its largest error and the first particle that has it, for
// rk_control to reduce. In float32 the state is two floats a coordinate (split_state.glsl): the
// step's change is formed from the old low part, then added to the high part without rounding.
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
layout(std430, binding = 15) writeonly buffer TrialVelocityLow { Real trial_velocity_low[]; };

layout(push_constant) uniform Constants { StagePassConstants constants; };  // stage: unused

#include "gpu/shaders/anchor_motion.glsl"
#include "gpu/shaders/error_reduction.glsl"
#if CLOTHSIM_STAGE_OFFSETS
#include "gpu/shaders/split_state.glsl"

// (high + change) as a split state, written to the trial arrays; the high parts returned.
Vec3 store_split_position(uint p, Vec3 high, Vec3 change) {
  for (uint k = 0u; k < 3u; ++k) {
    const SplitReal split = split_sum(high[k], change[k]);
    trial_position[3 * p + k] = split.high;
    trial_position_low[3 * p + k] = split.low;
    high[k] = split.high;
  }
  return high;
}

Vec3 store_split_velocity(uint p, Vec3 high, Vec3 change) {
  for (uint k = 0u; k < 3u; ++k) {
    const SplitReal split = split_sum(high[k], change[k]);
    trial_velocity[3 * p + k] = split.high;
    trial_velocity_low[3 * p + k] = split.low;
    high[k] = split.high;
  }
  return high;
}
#endif

Vec3 stage_acceleration(uint l, uint p) {
  const uint base = 3 * (l * constants.particle_count + p);
  return Vec3(acceleration[base], acceleration[base + 1], acceleration[base + 2]);
}

// h sum_l w_l (V_l, K_l) of row `row` in Nystrom form, added to (x, v) (zero bases for the error).
void combine(uint row, uint p, Real h, Vec3 v0, inout Vec3 x, inout Vec3 v) {
  const uint base = row * kRowReals;
  if (rows[base] != Real(0.0)) x += (h * rows[base]) * v0;
  for (uint l = 0u; l < constants.stages; ++l) {
    const Real position_weight = rows[base + 1u + l];
    const Real velocity_weight = rows[base + 1u + kMaxDeviceStages + l];
    if (position_weight == Real(0.0) && velocity_weight == Real(0.0)) continue;
    const Vec3 k = stage_acceleration(l, p);
    if (position_weight != Real(0.0)) x += (h * h * position_weight) * k;
    if (velocity_weight != Real(0.0)) v += (h * velocity_weight) * k;
  }
}

Real component_ratio(Real error, Real before, Real after) {
  const Real scale = control_real[kAbsoluteTolerance] + control_real[kRelativeTolerance] * max(abs(before), abs(after));
  return abs(error) / scale;
}

Real vector_ratio(Vec3 error, Vec3 before, Vec3 after) {
  return max(max(component_ratio(error.x, before.x, after.x), component_ratio(error.y, before.y, after.y)),
             component_ratio(error.z, before.z, after.z));
}

#if CLOTHSIM_STAGE_OFFSETS
// float32: the trial state as split values (split_state.glsl), each change formed from the old low
// part and added to the high part without rounding; the high parts returned for the error norm.
void trial_state(uint p, Real h, Vec3 x0, Vec3 v0, out Vec3 x1, out Vec3 v1) {
  const Vec3 low_x0 = Vec3(position_low[3 * p], position_low[3 * p + 1], position_low[3 * p + 2]);
  const Vec3 low_v0 = Vec3(velocity_low[3 * p], velocity_low[3 * p + 1], velocity_low[3 * p + 2]);
  const int anchor = particle_anchor[p];
  if (anchor >= 0) {
    const PathMotion motion = anchor_motion(uint(anchor), control_real[kElapsed] + h);
    x1 = store_split_position(p, motion.position, Vec3(0.0));
    v1 = store_split_velocity(p, motion.velocity, Vec3(0.0));
  } else if (constants.symplectic != 0u) {
    v1 = store_split_velocity(p, v0, low_v0 + h * stage_acceleration(0u, p));
    const Vec3 v1_low = Vec3(trial_velocity_low[3 * p], trial_velocity_low[3 * p + 1], trial_velocity_low[3 * p + 2]);
    x1 = store_split_position(p, x0, low_x0 + (h * v1 + h * v1_low));
  } else {
    Vec3 change_x = low_x0;
    Vec3 change_v = low_v0;
    combine(constants.stages, p, h, v0, change_x, change_v);
    const Real weight = rows[constants.stages * kRowReals];  // the solution row's weight of v0
    if (weight != Real(0.0)) change_x += (h * weight) * low_v0;
    x1 = store_split_position(p, x0, change_x);
    v1 = store_split_velocity(p, v0, change_v);
  }
}
#else
// float64: the trial state as the CPU forms it.
void trial_state(uint p, Real h, Vec3 x0, Vec3 v0, out Vec3 x1, out Vec3 v1) {
  x1 = x0;
  v1 = v0;
  const int anchor = particle_anchor[p];
  if (anchor >= 0) {
    const PathMotion motion = anchor_motion(uint(anchor), control_real[kElapsed] + h);
    x1 = motion.position;
    v1 = motion.velocity;
  } else if (constants.symplectic != 0u) {
    v1 = v0 + h * stage_acceleration(0u, p);
    x1 = x0 + h * v1;
  } else {
    combine(constants.stages, p, h, v0, x1, v1);
  }
  for (uint k = 0u; k < 3u; ++k) {
    trial_position[3 * p + k] = x1[k];
    trial_velocity[3 * p + k] = v1[k];
  }
}
#endif

void main() {
  if (control_uint[kActive] == 0u) return;  // the same for the whole dispatch
  const uint p = invocation_index();
  Real ratio = Real(0.0);
  if (p < constants.particle_count) {
    const Real h = control_real[kStep];
    const Vec3 x0 = Vec3(position[3 * p], position[3 * p + 1], position[3 * p + 2]);
    const Vec3 v0 = Vec3(velocity[3 * p], velocity[3 * p + 1], velocity[3 * p + 2]);
    Vec3 x1;
    Vec3 v1;
    trial_state(p, h, x0, v0, x1, v1);
    if (particle_anchor[p] < 0 && constants.symplectic == 0u && control_uint[kAdaptive] != 0u) {
      Vec3 error_x = Vec3(0.0);
      Vec3 error_v = Vec3(0.0);
      combine(constants.stages + 1u, p, h, v0, error_x, error_v);
      ratio = max(vector_ratio(error_x, x0, x1), vector_ratio(error_v, v0, v1));
    }
    ratio = bounded_error(ratio, x1, v1);
  }
  const uint group = workgroup_index();
  reduce_largest_error(ratio, p);
  if (gl_LocalInvocationID.x == 0u && group < (constants.particle_count + kReduceWorkgroup - 1u) / kReduceWorkgroup) {
    block_error[group] = largest_error[0];
    block_particle[group] = largest_particle[0];
  }
}
