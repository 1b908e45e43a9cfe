// The state of stage i of a Runge-Kutta step for one particle (ExplicitRungeKutta::compute_stages
// on the CPU): y_i = y + h sum_{j<i} a_ij (V_j, K_j) in Nystrom form (rows of device_step.h), term
// by term in the CPU's order, zero coefficients skipped; an anchored particle is put on its path at
// the stage time instead (ClothDynamics::constrain). Stage 0 is the state itself. In float32 the
// result is the offset from the state's high parts, starting from its low parts (stage_offsets.glsl,
// split_state.glsl). rk_stage_state writes it for the force passes; lattice_stage forms it where a
// spring needs it.
//
// The includer declares the state `origin_position`, `origin_velocity` (and in float32
// `origin_position_low`, `origin_velocity_low`), the stages' `acceleration`, `rows`,
// `control_real`, `particle_anchor` and `anchor_paths`, and `constants.particle_count`.
#ifndef CLOTHSIM_STAGE_STATE_GLSL
#define CLOTHSIM_STAGE_STATE_GLSL

#include "gpu/shaders/anchor_motion.glsl"
#include "gpu/shaders/stage_terms.glsl"  // the earlier stages' terms (CLOTHSIM_STAGE_ACCELERATION)
#include "gpu/shaders/stage_point.glsl"

Vec3 state_vector(uint array, uint p) {
  if (array == 0u) return Vec3(origin_position[3 * p], origin_position[3 * p + 1], origin_position[3 * p + 2]);
  return Vec3(origin_velocity[3 * p], origin_velocity[3 * p + 1], origin_velocity[3 * p + 2]);
}

#if CLOTHSIM_STAGE_OFFSETS
Vec3 state_low_vector(uint array, uint p) {
  if (array == 0u) {
    return Vec3(origin_position_low[3 * p], origin_position_low[3 * p + 1], origin_position_low[3 * p + 2]);
  }
  return Vec3(origin_velocity_low[3 * p], origin_velocity_low[3 * p + 1], origin_velocity_low[3 * p + 2]);
}
#endif

StagePoint stage_state(uint p, uint stage) {
  const Real h = control_real[kStep];
  const uint row = stage * kRowReals;
  Vec3 x;
  Vec3 v;
  const int anchor = particle_anchor[p];
  if (anchor >= 0) {
    // The stage's node c_i is the sum of its row's weights.
    const PathMotion motion = anchor_motion(uint(anchor), control_real[kElapsed] + rows[row] * h);
    x = motion.position;
    v = motion.velocity;
#if CLOTHSIM_STAGE_OFFSETS
    x = (x - state_vector(0u, p)) - state_low_vector(0u, p);
    v = (v - state_vector(1u, p)) - state_low_vector(1u, p);
#endif
  } else {
    const Vec3 v0 = state_vector(1u, p);
#if CLOTHSIM_STAGE_OFFSETS
    x = state_low_vector(0u, p);
    v = state_low_vector(1u, p);
    if (rows[row] != Real(0.0)) x += (h * rows[row]) * v0 + (h * rows[row]) * v;
#else
    x = state_vector(0u, p);
    v = v0;
    if (rows[row] != Real(0.0)) x += (h * rows[row]) * v0;
#endif
    add_stage_terms(stage, stage, p, h, x, v);
  }
  StagePoint point;
  point.position = x;
  point.velocity = v;
  return point;
}

#endif
