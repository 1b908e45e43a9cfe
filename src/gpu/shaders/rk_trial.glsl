// A particle's trial state at the end of an attempt and its scaled error
// (ExplicitRungeKutta::combine_solution with an error row on the CPU,
// AdaptiveRungeKutta::solution_and_error): y + h sum_l b_l (V_l, K_l) (or symplectic Euler's
// v + h K_0, x + h v_new), an anchored particle its path's state at the step's end, and, under
// error control, max_k |e_k| / (atol + rtol max(|y_k|, |y_new,k|)) with
// e = h sum_l (b_l - b^_l) (V_l, K_l); without it, 0. A non-finite trial or error counts as
// kHugeError. In float32 the state is two floats a coordinate (split_state.glsl): the step's
// change is formed from the old low part, then added to the high part without rounding.
// rk_solution forms it after the stages; lattice_stage in its last stage's pass.
//
// The includer declares `rows`, `control_real`, `control_uint`, `particle_anchor`,
// `anchor_paths`, `trial_position`, `trial_velocity` (float32: `trial_position_low`,
// `trial_velocity_low`), the stages' `acceleration` and the push constants `constants` with
// `stages` and `particle_count`; K_l as stage_terms.glsl reads it.
#ifndef CLOTHSIM_RK_TRIAL_GLSL
#define CLOTHSIM_RK_TRIAL_GLSL

#include "gpu/shaders/anchor_motion.glsl"
#include "gpu/shaders/error_reduction.glsl"
#include "gpu/shaders/stage_terms.glsl"
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

// h sum_l w_l (V_l, K_l) of row `row` in Nystrom form, added to (x, v) (zero bases for the error).
void combine(uint row, uint p, Real h, Vec3 v0, inout Vec3 x, inout Vec3 v) {
  if (rows[row * kRowReals] != Real(0.0)) x += (h * rows[row * kRowReals]) * v0;
  add_stage_terms(row, constants.stages, p, h, x, v);
}

Real component_ratio(Real error, Real before, Real after) {
  const Real scale = control_real[kAbsoluteTolerance] + control_real[kRelativeTolerance] * max(abs(before), abs(after));
  return abs(error) / scale;
}

Real vector_ratio(Vec3 error, Vec3 before, Vec3 after) {
  return max(max(component_ratio(error.x, before.x, after.x), component_ratio(error.y, before.y, after.y)),
             component_ratio(error.z, before.z, after.z));
}

// The state at the step's start: its high parts (x0, v0) and, in float32, its low parts.
struct StepStart {
  Vec3 x0;
  Vec3 v0;
  Vec3 low_x0;
  Vec3 low_v0;
};

#if CLOTHSIM_STAGE_OFFSETS
// float32: the trial state as split values (split_state.glsl), each change formed from the old low
// part and added to the high part without rounding; the high parts returned for the error norm.
void trial_state(uint p, Real h, bool symplectic, StepStart start, out Vec3 x1, out Vec3 v1) {
  const int anchor = particle_anchor[p];
  if (anchor >= 0) {
    const PathMotion motion = anchor_motion(uint(anchor), control_real[kElapsed] + h);
    x1 = store_split_position(p, motion.position, Vec3(0.0));
    v1 = store_split_velocity(p, motion.velocity, Vec3(0.0));
  } else if (symplectic) {
    v1 = store_split_velocity(p, start.v0, start.low_v0 + h * CLOTHSIM_STAGE_ACCELERATION(0u, p));
    const Vec3 v1_low = Vec3(trial_velocity_low[3 * p], trial_velocity_low[3 * p + 1], trial_velocity_low[3 * p + 2]);
    x1 = store_split_position(p, start.x0, start.low_x0 + (h * v1 + h * v1_low));
  } else {
    Vec3 change_x = start.low_x0;
    Vec3 change_v = start.low_v0;
    combine(constants.stages, p, h, start.v0, change_x, change_v);
    const Real weight = rows[constants.stages * kRowReals];  // the solution row's weight of v0
    if (weight != Real(0.0)) change_x += (h * weight) * start.low_v0;
    x1 = store_split_position(p, start.x0, change_x);
    v1 = store_split_velocity(p, start.v0, change_v);
  }
}
#else
// float64: the trial state as the CPU forms it.
void trial_state(uint p, Real h, bool symplectic, StepStart start, out Vec3 x1, out Vec3 v1) {
  x1 = start.x0;
  v1 = start.v0;
  const int anchor = particle_anchor[p];
  if (anchor >= 0) {
    const PathMotion motion = anchor_motion(uint(anchor), control_real[kElapsed] + h);
    x1 = motion.position;
    v1 = motion.velocity;
  } else if (symplectic) {
    v1 = start.v0 + h * CLOTHSIM_STAGE_ACCELERATION(0u, p);
    x1 = start.x0 + h * v1;
  } else {
    combine(constants.stages, p, h, start.v0, x1, v1);
  }
  for (uint k = 0u; k < 3u; ++k) {
    trial_position[3 * p + k] = x1[k];
    trial_velocity[3 * p + k] = v1[k];
  }
}
#endif

// Writes p's trial state and returns its scaled error, bounded (error_reduction.glsl).
Real trial_and_error(uint p, bool symplectic, StepStart start) {
  const Real h = control_real[kStep];
  Vec3 x1;
  Vec3 v1;
  trial_state(p, h, symplectic, start, x1, v1);
  Real ratio = Real(0.0);
  if (particle_anchor[p] < 0 && !symplectic && control_uint[kAdaptive] != 0u) {
    Vec3 error_x = Vec3(0.0);
    Vec3 error_v = Vec3(0.0);
    combine(constants.stages + 1u, p, h, start.v0, error_x, error_v);
    ratio = max(vector_ratio(error_x, start.x0, x1), vector_ratio(error_v, start.v0, v1));
  }
  return bounded_error(ratio, x1, v1);
}

#endif
