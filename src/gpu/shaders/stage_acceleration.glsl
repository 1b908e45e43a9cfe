// A particle's acceleration in stage i (ClothDynamics::evaluate on the CPU), from the force on it:
// the force divided by its mass, or for an anchored particle its path's acceleration, and the
// power its anchor puts in, v . (m a - f). Writes K_i and the particle's drag and anchor powers for
// the stage, which rk_accept weighs into the step's work. stage_acceleration runs it after the
// force passes; lattice_stage after forming the force itself, for each of its stages, keeping the
// last stage's K_i for the trial solution it forms at once.
//
// The includer declares `particle_mass`, `inverse_mass`, `environment`, `rows`, `control_real`,
// `particle_anchor`, `anchor_paths`, `acceleration`, `particle_power` and the push constants
// `constants` with particle_count, stage and stages.
#ifndef CLOTHSIM_STAGE_ACCELERATION_GLSL
#define CLOTHSIM_STAGE_ACCELERATION_GLSL

#include "gpu/shaders/anchor_motion.glsl"
#include "gpu/shaders/environment_force.glsl"

// The lattice path's force on p: gravity and drag, its own springs' force on it, and each
// neighbour's springs' force on it (`from`, by direction: 0 east, 1 south, 2 west, 3 north), added
// east, south, west, north.
Vec3 lattice_force_on(uint p, Vec3 v, Vec3 own, bool has[4], Vec3 from[4]) {
  Vec3 sum = environment_force(p, v);
  sum += own;
  for (uint d = 0u; d < 4u; ++d) {
    if (has[d]) sum += from[d];
  }
  return sum;
}

// K of p in stage `stage` from the force on it, and the power its anchor puts in.
struct StageAcceleration {
  Vec3 a;             // m/s^2
  Real anchor_power;  // W
};

StageAcceleration stage_acceleration_from(uint p, uint stage, Vec3 v, Vec3 force) {
  StageAcceleration k;
  k.a = inverse_mass[p] * force;
  k.anchor_power = Real(0.0);
  const int anchor = particle_anchor[p];
  if (anchor >= 0) {
    const Real tau = control_real[kElapsed] + rows[stage * kRowReals] * control_real[kStep];
    k.a = anchor_motion(uint(anchor), tau).acceleration;
    k.anchor_power = dot(v, particle_mass[p] * k.a - force);
  }
  return k;
}

// A particle's drag and anchor powers in stage `stage` added to their sums over the stages,
// weighed by the solution row (device_step.h).
void add_stage_powers(uint stage, Vec3 v, Real anchor_power, inout Real drag_sum, inout Real anchor_sum) {
  const Real weight = rows[solution_weight_slot(constants.stages, stage)];
  const bool first = stage == 0u;
  drag_sum = (first ? Real(0.0) : drag_sum) + weight * (-environment[3] * dot(v, v));
  anchor_sum = (first ? Real(0.0) : anchor_sum) + weight * anchor_power;
}

void store_acceleration(uint p, uint stage, Vec3 a) {
  const uint base = 3 * (stage * constants.particle_count + p);
  acceleration[base] = a.x;
  acceleration[base + 1] = a.y;
  acceleration[base + 2] = a.z;
}

// stage_acceleration's whole work for p in stage constants.stage.
void store_stage_acceleration(uint p, Vec3 v, Vec3 force) {
  const StageAcceleration k = stage_acceleration_from(p, constants.stage, v, force);
  const uint n = constants.particle_count;
  add_stage_powers(constants.stage, v, k.anchor_power, particle_power[p], particle_power[n + p]);
  store_acceleration(p, constants.stage, k.a);
}

#endif
