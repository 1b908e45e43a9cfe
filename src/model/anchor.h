// Anchored particles: fixed in space, or moved along a prescribed path.
//
// An anchored particle is not integrated: at every stage time t its position, velocity and
// acceleration are those of its path (see integrators/dynamics.cpp). Paths are closed-form so
// that stages inside an RKF45 step see the exact anchor position, not an integrated estimate.
//
// A driven path is the runtime anchor of the interactive viewer and of scripts (a particle held
// by the mouse): a straight segment at constant velocity from `origin` at `start_time` to its
// target at `end_time`, at rest there afterwards. The Simulation re-aims it between steps
// (Simulation::drive_particle) and never lets a step cross `end_time`, so every step sees a
// smooth path and the stop is an event between steps, where its impulse is booked as anchor work.
// Rejected: setting the particle's position from outside without a velocity. The springs would
// see a jump, and the energy balance would miss the work the hand does on the sheet.
#pragma once

#include <cstdint>
#include <limits>

#include "core/vec3.h"

namespace clothsim {

enum class AnchorPathKind : std::uint8_t {
  fixed,     // x(t) = origin
  linear,    // x(t) = origin + velocity t
  sinusoid,  // x(t) = origin + amplitude (sin(2 pi f t + phase) - sin(phase))
  driven,    // x(t) = origin + velocity (min(t, end_time) - start_time); runtime only, never in a scene
};

struct AnchorPath {
  AnchorPathKind kind = AnchorPathKind::fixed;
  Vec3 origin;          // position at t = 0, m
  Vec3 velocity;        // linear: constant velocity, m/s
  Vec3 amplitude;       // sinusoid: displacement amplitude, m
  double frequency = 0.0;  // sinusoid: Hz
  double phase = 0.0;      // sinusoid: rad
  double start_time = 0.0;  // driven: s, when the particle is at `origin`
  double end_time = std::numeric_limits<double>::infinity();  // driven: s, arrival at the target

  // A path that stays at `origin`.
  static AnchorPath fixed_at(const Vec3& origin) {
    AnchorPath path;
    path.origin = origin;
    return path;
  }

  Vec3 position(double t) const;
  // A driven path has its moving velocity up to and including end_time (the limit from inside
  // the last step before the stop) and zero after it.
  Vec3 velocity_at(double t) const;
  Vec3 acceleration(double t) const;
};

struct Anchor {
  std::uint32_t particle = 0;  // particle index
  AnchorPath path;
  // When the anchor lets go, s: from then on the particle is free and keeps the velocity its
  // path gave it. An event between steps (no step crosses it); +inf: never.
  double release_time = std::numeric_limits<double>::infinity();
};

}  // namespace clothsim
