// An anchored particle's motion over an advance, from its row of `anchor_paths` (device_step.h,
// kPathReals; path_motion.glsl). The includer declares `anchor_paths`.
#ifndef CLOTHSIM_ANCHOR_MOTION_GLSL
#define CLOTHSIM_ANCHOR_MOTION_GLSL
#include "gpu/shaders/path_motion.glsl"

PathMotion anchor_motion(uint anchor, Real tau) {
  const uint base = anchor * kPathReals;
  return path_motion(Vec3(anchor_paths[base], anchor_paths[base + 1], anchor_paths[base + 2]),
                     Vec3(anchor_paths[base + 3], anchor_paths[base + 4], anchor_paths[base + 5]),
                     Vec3(anchor_paths[base + 6], anchor_paths[base + 7], anchor_paths[base + 8]),
                     anchor_paths[base + 9], anchor_paths[base + 10], tau);
}

#endif
