// A Nystrom row's terms on the stages' accelerations of a particle: the one sum that forms a stage
// state (stage_state.glsl), a trial state and its error (rk_trial.glsl). K_l comes from
// stage_accelerations.glsl's arrays, unless the includer defines CLOTHSIM_STAGE_ACCELERATION(l, p)
// first (lattice_stage: the stages it formed itself, from shared memory and registers). The
// includer declares `rows`.
#ifndef CLOTHSIM_STAGE_TERMS_GLSL
#define CLOTHSIM_STAGE_TERMS_GLSL

#include "gpu/shaders/stage_accelerations.glsl"
#ifndef CLOTHSIM_STAGE_ACCELERATION
#define CLOTHSIM_STAGE_ACCELERATION stage_acceleration_of
#endif

// The terms of row `row` of `rows` (device_step.h: a stage's, the solution's, the error's) on the
// first `count` stages of particle p, added in the CPU's order with zero weights skipped:
// h^2 w_x,l K_l to x and h w_v,l K_l to v.
void add_stage_terms(uint row, uint count, uint p, Real h, inout Vec3 x, inout Vec3 v) {
  const uint base = row * kRowReals;
  for (uint l = 0u; l < count; ++l) {
    const Real position_weight = rows[base + 1u + l];
    const Real velocity_weight = rows[base + 1u + kMaxDeviceStages + l];
    if (position_weight == Real(0.0) && velocity_weight == Real(0.0)) continue;
    const Vec3 k = CLOTHSIM_STAGE_ACCELERATION(l, p);
    if (position_weight != Real(0.0)) x += (h * h * position_weight) * k;
    if (velocity_weight != Real(0.0)) v += (h * velocity_weight) * k;
  }
}

#endif
