// How the force passes read a Runge-Kutta stage's state (docs/gpu.md, "float32 that keeps its
// accuracy").
//
// float64: the stage arrays hold the stage's positions and velocities, y_i = y + h sum_j a_ij K_j,
// as on the CPU.
//
// float32: they hold the offsets y_i - y from the step's start y (the state arrays' high parts;
// the offsets start from the low parts, split_state.glsl), and a pass
// forms what it needs near a particle `origin` of its element as (y[q] - y[origin]) + (offset[q] -
// offset[origin]). Stored whole, a stage's coordinates would be rounded to float each stage, by
// up to 1e-6 m at 16 m from the origin: noise of a different draw in every stage, which the
// error estimate (a weighted difference of the stages' accelerations) sees as error, so that
// RKF45 took 1.1 to 1.7 times the steps of float64 on the paper's scenes. As offsets, each stage
// is rounded to float at the scale of its own motion (about 1e-10 m), and the step's start, the
// same in every stage, drops out of the error estimate. The element formulas see positions and
// velocities relative to the origin; they depend only on differences (and the damping power on
// relative velocities), so the forces are the same.
//
// The includer declares the stage arrays `position` and `velocity` and the state arrays
// `origin_position` and `origin_velocity` (bound in both precisions; float64 reads only the first
// two), or, with CLOTHSIM_STAGE_VELOCITY_ONLY defined, the velocities alone.
#ifndef CLOTHSIM_STAGE_OFFSETS_GLSL
#define CLOTHSIM_STAGE_OFFSETS_GLSL

#include "gpu/shaders/device_step.h"  // CLOTHSIM_STAGE_OFFSETS

#include "gpu/shaders/stage_point.glsl"

// GLSL passes no buffer to a function: one reader per array. An includer that defines
// CLOTHSIM_STAGE_COMPUTED has no stage arrays: it defines stage_offset_point(q), formed from the
// state where it is needed (lattice_stage, from stage_state.glsl), and reads no stage velocity
// alone.
Vec3 origin_velocity_of(uint q) {
  return Vec3(origin_velocity[3 * q], origin_velocity[3 * q + 1], origin_velocity[3 * q + 2]);
}

// float32: particle q's stage value relative to particle `origin`'s, from the two particles'
// values at the step's start and their stage offsets. The step's start, the same in every stage,
// drops out of a difference of two stages' values.
Vec3 offset_between(Vec3 start_q, Vec3 start_origin, Vec3 stage_q, Vec3 stage_origin) {
  return (start_q - start_origin) + (stage_q - stage_origin);
}

// The stage velocity itself of particle q, from what the stage arrays hold (for drag and the
// anchors' power).
Vec3 stage_velocity_from(uint q, Vec3 stage_velocity) {
#if CLOTHSIM_STAGE_OFFSETS
  return origin_velocity_of(q) + stage_velocity;
#else
  return stage_velocity;
#endif
}

#ifndef CLOTHSIM_STAGE_COMPUTED
Vec3 stage_offset_velocity(uint q) { return Vec3(velocity[3 * q], velocity[3 * q + 1], velocity[3 * q + 2]); }

// Particle q's stage velocity, relative to particle `origin`'s in float32.
Vec3 stage_velocity_near(uint q, uint origin) {
#if CLOTHSIM_STAGE_OFFSETS
  if (q == origin) return Vec3(0.0);
  return offset_between(origin_velocity_of(q), origin_velocity_of(origin), stage_offset_velocity(q),
                        stage_offset_velocity(origin));
#else
  return stage_offset_velocity(q);
#endif
}

Vec3 stage_velocity(uint q) { return stage_velocity_from(q, stage_offset_velocity(q)); }
#endif

#ifndef CLOTHSIM_STAGE_VELOCITY_ONLY
Vec3 origin_position_of(uint q) {
  return Vec3(origin_position[3 * q], origin_position[3 * q + 1], origin_position[3 * q + 2]);
}

#ifndef CLOTHSIM_STAGE_COMPUTED
Vec3 stage_offset_position(uint q) { return Vec3(position[3 * q], position[3 * q + 1], position[3 * q + 2]); }

// Particle q's stage position, relative to particle `origin`'s in float32.
Vec3 stage_position_near(uint q, uint origin) {
#if CLOTHSIM_STAGE_OFFSETS
  if (q == origin) return Vec3(0.0);
  return offset_between(origin_position_of(q), origin_position_of(origin), stage_offset_position(q),
                        stage_offset_position(origin));
#else
  return stage_offset_position(q);
#endif
}

StagePoint stage_offset_point(uint q) {
  StagePoint point;
  point.position = stage_offset_position(q);
  point.velocity = stage_offset_velocity(q);
  return point;
}
#endif

// Particle q's stage state `stage` (its stage_offset_point), relative in float32 to particle
// `origin`'s, whose own is `at_origin`: what stage_position_near and stage_velocity_near give.
StagePoint stage_point_relative(uint q, StagePoint stage, uint origin, StagePoint at_origin) {
#if CLOTHSIM_STAGE_OFFSETS
  StagePoint point;
  if (q == origin) {
    point.position = Vec3(0.0);
    point.velocity = Vec3(0.0);
    return point;
  }
  point.position =
      offset_between(origin_position_of(q), origin_position_of(origin), stage.position, at_origin.position);
  point.velocity =
      offset_between(origin_velocity_of(q), origin_velocity_of(origin), stage.velocity, at_origin.velocity);
  return point;
#else
  return stage;
#endif
}
#endif

#endif
