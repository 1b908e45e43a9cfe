// Gravity and air drag on particle p at velocity v: the first terms of every particle's force
// (forces/forces.cpp), for the general path's gather (gather.glsl) and the lattice path's
// (stage_acceleration.glsl). The includer declares `particle_mass` and `environment` (gravity x,
// y, z, then drag).
#ifndef CLOTHSIM_ENVIRONMENT_FORCE_GLSL
#define CLOTHSIM_ENVIRONMENT_FORCE_GLSL

Vec3 environment_force(uint p, Vec3 v) {
  const Vec3 gravity = Vec3(environment[0], environment[1], environment[2]);
  const Real drag = environment[3];
  return particle_mass[p] * gravity - drag * v;
}

#endif
