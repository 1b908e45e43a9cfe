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
#include <vector>

#include "core/vec3.h"

namespace clothsim {

enum class AnchorPathKind : std::uint8_t {
  fixed,      // x(t) = origin
  linear,     // x(t) = origin + velocity t
  sinusoid,   // x(t) = origin + amplitude (sin(2 pi f t + phase) - sin(phase))
  keyframes,  // x(t) = origin + the keys' offsets interpolated linearly in t (see AnchorKey)
  driven,     // x(t) = origin + velocity (min(t, end_time) - start_time); runtime only, never in a scene
};

// One key of a keyframed path: where the particle is at `time`, as an offset from the path's
// origin (so one key list moves a whole row of anchors together). Between keys the particle moves
// in a straight line at the segment's constant velocity; before the first key it holds the first,
// after the last it holds the last. Keys are velocity discontinuities: the Simulation makes each
// key time an anchor event that no step crosses (next_key_after), so every step sees one
// straight segment.
struct AnchorKey {
  double time = 0.0;  // s; keys are in strictly increasing time
  Vec3 offset{};      // displacement from the path's origin, m

  bool operator==(const AnchorKey&) const = default;
};

struct AnchorPath {
  AnchorPathKind kind = AnchorPathKind::fixed;
  Vec3 origin;                                                // position at t = 0, m
  Vec3 velocity;                                              // linear: constant velocity, m/s
  Vec3 amplitude;                                             // sinusoid: displacement amplitude, m
  double frequency = 0.0;                                     // sinusoid: Hz
  double phase = 0.0;                                         // sinusoid: rad
  double start_time = 0.0;                                    // driven: s, when the particle is at `origin`
  double end_time = std::numeric_limits<double>::infinity();  // driven: s, arrival at the target
  std::vector<AnchorKey> keys{};                              // keyframes: at least one, strictly increasing in time

  // A path that stays at `origin`.
  static AnchorPath fixed_at(const Vec3& origin) {
    AnchorPath path;
    path.origin = origin;
    return path;
  }

  Vec3 position(double t) const;
  // A driven path has its moving velocity up to and including end_time (the limit from inside
  // the last step before the stop) and zero after it.
  // A keyframed path has, exactly at a key, the velocity of the segment that starts there (the
  // right limit; zero at and after the last key): a step never crosses a key, so the steps after
  // a key see that segment's velocity from their first stage on, and an anchor released at a key
  // keeps the velocity it was about to follow (a release at the last key lets go of a held,
  // motionless particle).
  Vec3 velocity_at(double t) const;
  // The velocity just before t (the left limit). The same as velocity_at(t) except at a key of a
  // keyframed path, where the particle's velocity jumps: the Simulation books that jump's kinetic
  // energy as anchor work at the key (an impulse the anchor gives its particle).
  Vec3 velocity_before(double t) const;
  Vec3 acceleration(double t) const;  // keyframes: zero (between keys the motion is uniform)
  // Keyframes: the time of the first key after `t` (strictly), +inf if none; +inf for every other
  // kind. The Simulation stops steps there (Simulation::next_anchor_event).
  double next_key_after(double t) const;
};

struct Anchor {
  std::uint32_t particle = 0;  // particle index
  AnchorPath path;
  // When the anchor lets go, s: from then on the particle is free and keeps the velocity its
  // path gave it. An event between steps (no step crosses it); +inf: never.
  double release_time = std::numeric_limits<double>::infinity();
};

}  // namespace clothsim
