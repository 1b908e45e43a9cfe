// K_l of particle p, from the stages' accelerations, [stages][3 particles] (device_step.h). The
// includer declares `acceleration` and `constants.particle_count`.
#ifndef CLOTHSIM_STAGE_ACCELERATIONS_GLSL
#define CLOTHSIM_STAGE_ACCELERATIONS_GLSL

Vec3 stage_acceleration_of(uint l, uint p) {
  const uint base = 3 * (l * constants.particle_count + p);
  return Vec3(acceleration[base], acceleration[base + 1], acceleration[base + 2]);
}

#endif
