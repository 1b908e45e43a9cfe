// A particle's acceleration in stage i (ClothDynamics::evaluate on the CPU), from the force on it:
// the force divided by its mass, or for an anchored particle its path's acceleration, and the
// power its anchor puts in, v . (m a - f). Writes K_i and the particle's drag and anchor powers for
// the stage, which rk_accept weighs into the step's work. stage_acceleration runs it after the
// force passes; lattice_stage after forming the force itself, and in an attempt's last stage keeps
// K_i for the trial solution it forms at once.
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

// K_i of p from the force on it, with its drag and anchor powers for the stage written.
Vec3 acceleration_and_powers(uint p, Vec3 v, Vec3 force) {
  const uint n = constants.particle_count;
  Vec3 a = inverse_mass[p] * force;
  Real anchor_power = Real(0.0);
  const int anchor = particle_anchor[p];
  if (anchor >= 0) {
    const Real tau = control_real[kElapsed] + rows[constants.stage * kRowReals] * control_real[kStep];
    a = anchor_motion(uint(anchor), tau).acceleration;
    anchor_power = dot(v, particle_mass[p] * a - force);
  }
  // The powers weighed by the solution row, summed over the stages (device_step.h).
  const Real weight = rows[solution_weight_slot(constants.stages, constants.stage)];
  const bool first = constants.stage == 0u;
  particle_power[p] = (first ? Real(0.0) : particle_power[p]) + weight * (-environment[3] * dot(v, v));
  particle_power[n + p] = (first ? Real(0.0) : particle_power[n + p]) + weight * anchor_power;
  return a;
}

void store_stage_acceleration(uint p, Vec3 v, Vec3 force) {
  const Vec3 a = acceleration_and_powers(p, v, force);
  const uint base = 3 * (constants.stage * constants.particle_count + p);
  acceleration[base] = a.x;
  acceleration[base + 1] = a.y;
  acceleration[base + 2] = a.z;
}

#endif
