// The error norm of the adaptive integrators (RKF45, explicit_runge_kutta.h; the IMEX pair,
// imex.h): a step is accepted when every free coordinate's error estimate e_i satisfies
// |e_i| <= atol + rtol max(|y_i|, |y_new,i|), in the max norm over positions and velocities. One
// definition, so that both methods accept a step on the same criterion.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "core/vec3.h"

namespace clothsim {

// The scaled error of one particle as the bit pattern of a non-negative double: for those,
// unsigned integer order is numeric order, with +inf above every finite value and NaN above +inf,
// so a plain integer maximum finds the largest error and lets a non-finite one win, without
// branches. 0 for anchored particles.
[[gnu::always_inline]] inline std::uint64_t scaled_error_bits(const Vec3& error_x, const Vec3& error_v, const Vec3& x0,
                                                              const Vec3& x1, const Vec3& v0, const Vec3& v1,
                                                              double atol, double rtol, bool anchored) {
  const auto ratio = [&](double error, double before, double after) {
    const double scale = atol + rtol * std::max(std::abs(before), std::abs(after));
    // (e - e) and (after - after) are 0 for finite values and NaN otherwise.
    const double ratio_value = std::abs(error) / scale + ((error - error) + (after - after));
    return std::bit_cast<std::uint64_t>(std::abs(ratio_value));
  };
  const std::uint64_t largest = std::max(std::max(std::max(ratio(error_x.x, x0.x, x1.x), ratio(error_x.y, x0.y, x1.y)),
                                                  std::max(ratio(error_x.z, x0.z, x1.z), ratio(error_v.x, v0.x, v1.x))),
                                         std::max(ratio(error_v.y, v0.y, v1.y), ratio(error_v.z, v0.z, v1.z)));
  return anchored ? 0 : largest;
}

}  // namespace clothsim
