// Anchored particles: fixed in space, or moved along a prescribed path.
//
// An anchored particle is not integrated: at every stage time t its position, velocity and
// acceleration are those of its path (see integrators/dynamics.cpp). Paths are closed-form so
// that stages inside an RKF45 step see the exact anchor position, not an integrated estimate.
#pragma once

#include <cstdint>

#include "core/vec3.h"

namespace clothsim {

enum class AnchorPathKind : std::uint8_t {
  fixed,     // x(t) = origin
  linear,    // x(t) = origin + velocity t
  sinusoid,  // x(t) = origin + amplitude (sin(2 pi f t + phase) - sin(phase))
};

struct AnchorPath {
  AnchorPathKind kind = AnchorPathKind::fixed;
  Vec3 origin;          // position at t = 0, m
  Vec3 velocity;        // linear: constant velocity, m/s
  Vec3 amplitude;       // sinusoid: displacement amplitude, m
  double frequency = 0.0;  // sinusoid: Hz
  double phase = 0.0;      // sinusoid: rad

  // A path that stays at `origin`.
  static AnchorPath fixed_at(const Vec3& origin) {
    AnchorPath path;
    path.origin = origin;
    return path;
  }

  Vec3 position(double t) const;
  Vec3 velocity_at(double t) const;
  Vec3 acceleration(double t) const;
};

struct Anchor {
  std::uint32_t particle = 0;  // particle index
  AnchorPath path;
};

}  // namespace clothsim
