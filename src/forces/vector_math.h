// Elementary functions written so that the compiler can vectorise the loops that call them: the
// C++ spelling of forces/arctangent.inc, the arctangent the lattice kernel and the compute shaders
// share (its comment gives the method and its accuracy), in double and in float.
//
// std::atan2 is a call into libm: GCC cannot vectorise a loop that contains it (glibc's vector
// variants are declared only under -ffast-math, which clothsim does not use). The structured
// force kernel needs one arctangent per radial spring, six per particle, so it uses this inline,
// branch-free version instead. The float version serves the lattice kernel's float32 forces
// (lattice_kernel.h): one formula for both precisions.
#pragma once

#include <cmath>
#include <type_traits>

#include "core/shared_text.h"

namespace clothsim::vector_math {

namespace float64 {
using Real = double;
using std::abs;
#define CLOTHSIM_FLOAT64 1
#include "forces/arctangent.inc"
#undef CLOTHSIM_FLOAT64
}  // namespace float64

namespace float32 {
using Real = float;
using std::abs;
#define CLOTHSIM_FLOAT64 0
#include "forces/arctangent.inc"
#undef CLOTHSIM_FLOAT64
}  // namespace float32

// The angle atan2(y, x) in [0, pi/2] for y >= 0 and x >= 0, not both zero, in Real's precision.
template <typename Real>
[[gnu::always_inline]] inline Real atan2_first_quadrant(Real y, Real x) {
  static_assert(std::is_same_v<Real, double> || std::is_same_v<Real, float>);
  if constexpr (std::is_same_v<Real, double>) {
    return float64::arctangent_first_quadrant(y, x);
  } else {
    return float32::arctangent_first_quadrant(y, x);
  }
}

// The angle atan2(y, x) in [0, pi] for y >= 0 (atan2(0, 0) = 0), in Real's precision.
template <typename Real>
[[gnu::always_inline]] inline Real atan2_upper_half(Real y, Real x) {
  if constexpr (std::is_same_v<Real, double>) {
    return float64::arctangent_upper_half(y, x);
  } else {
    return float32::arctangent_upper_half(y, x);
  }
}

}  // namespace clothsim::vector_math
