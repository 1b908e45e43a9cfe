// The rows of paths the device reads (device_step.h, kPathReals; gpu/shaders/path_motion.glsl):
// an AnchorPath over one advance, relative to its start t0 (tau = t - t0), as
// x(tau) = x0 + v tau + A (sin(theta0 + omega tau) - sin theta0). Between two of the path's events
// (a key of a keyframed path, a driven path's end) every kind has that form: fixed and linear with
// A = 0, a keyframed or driven path on its current segment, a sinusoid with v = 0. Anchors' rows
// give their positions; colliders' rows give their shapes' offsets, x0 measured from `origin`.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <vector>

#include "core/vec3.h"
#include "gpu/shaders/device_step.h"
#include "model/anchor.h"

namespace clothsim::gpu {

// The anchors' path rows a device integrator allocates for `anchors`: at least 16, so that pins
// added at run time rarely make it grow the table (and record its passes again).
inline std::uint32_t anchor_row_capacity(std::size_t anchors) {
  return static_cast<std::uint32_t>(std::max<std::size_t>(anchors, 16));
}

// Appends the kPathReals of `path` over an advance from t0, its position measured from `origin`.
// theta0 is reduced to [-pi, pi], so that the device's sine sees a small argument.
inline void append_path_row(std::vector<double>& rows, const AnchorPath& path, double t0, const Vec3& origin) {
  const Vec3 x0 = path.position(t0) - origin;
  Vec3 v = path.velocity_at(t0);
  Vec3 amplitude;
  double omega = 0.0;
  double theta0 = 0.0;
  if (path.kind == AnchorPathKind::sinusoid) {
    v = Vec3{};
    amplitude = path.amplitude;
    omega = 2.0 * std::numbers::pi * path.frequency;
    theta0 = std::remainder(omega * t0 + path.phase, 2.0 * std::numbers::pi);
  }
  rows.insert(rows.end(), {x0.x, x0.y, x0.z, v.x, v.y, v.z, amplitude.x, amplitude.y, amplitude.z, omega, theta0});
  static_assert(kPathReals == 11, "the row written here is device_step.h's");
}

}  // namespace clothsim::gpu
