// Elementary functions written so that the compiler can vectorise the loops that call them.
//
// std::atan2 is a call into libm: GCC cannot vectorise a loop that contains it (glibc's vector
// variants are declared only under -ffast-math, which clothsim does not use). The structured
// force kernel needs one arctangent per radial spring, six per particle, so it uses this inline,
// branch-free version instead: only +, *, / and selects, which the vectoriser turns into
// straight-line SIMD code with blends.
//
// Accuracy: the rational approximation of atan on [-0.66, 0.66] and the range reduction are
// those of the Cephes library (S. L. Moshier, "Methods and Programs for Mathematical Functions",
// 1989; cephes/double/atan.c), whose stated peak relative error is 1.8e-16 (about 1 ulp) in IEEE
// double. tests/forces/test_vector_math.cpp compares it with std::atan2 over the whole range.
#pragma once

namespace clothsim::vector_math {

// The angle atan2(y, x) in [0, pi/2] for y >= 0 and x >= 0, not both zero. Branch-free.
//
// With r = min(x, y) / max(x, y) in [0, 1]:
//   y <= x:  atan(r)                 (reduced with tan(pi/4 + t) when r > 0.66)
//   y >  x:  pi/2 - atan(r)          (reduced with tan(pi/4 - t) when r >= tan(pi/8))
// which are Cephes' three intervals [0, 0.66], (0.66, tan(3 pi/8)], (tan(3 pi/8), inf) for the
// ratio y / x, reached without forming that ratio (it overflows as x -> 0).
inline double atan2_first_quadrant(double y, double x) {
  constexpr double kPiOver2 = 1.57079632679489661923;
  constexpr double kPiOver4 = 0.78539816339744830962;
  constexpr double kTanPiOver8 = 0.41421356237309504880;  // 1 / tan(3 pi / 8)
  // pi/2 - kPiOver2 (the part of pi/2 below the double's last bit), Cephes' MOREBITS.
  constexpr double kPiOver2Tail = 6.123233995736765886130e-17;
  const bool swapped = y > x;
  const double numerator = swapped ? x : y;
  const double denominator = swapped ? y : x;
  const double r = numerator / denominator;
  // Reduce above 0.66 (ratio y/x up to tan(3 pi/8)), or, when swapped, above tan(pi/8) (ratio
  // y/x below tan(3 pi/8)). Selects of doubles only: GCC 12 fails to vectorise selects between
  // boolean values.
  const double threshold = swapped ? kTanPiOver8 : 0.66;
  const bool reduced = r > threshold;
  const double sign = swapped ? -1.0 : 1.0;
  // The argument t of the polynomial, |t| <= 0.66.
  const double t = reduced ? sign * ((r - 1.0) / (r + 1.0)) : sign * r;
  const double unreduced_base = swapped ? kPiOver2 : 0.0;
  const double unreduced_tail = swapped ? kPiOver2Tail : 0.0;
  const double base = reduced ? kPiOver4 : unreduced_base;
  const double tail = reduced ? 0.5 * kPiOver2Tail : unreduced_tail;
  const double z = t * t;
  const double p = (((-8.750608600031904122785e-1 * z - 1.615753718733365076637e1) * z - 7.500855792314704667340e1) * z -
                    1.228866684490136173410e2) *
                       z -
                   6.485021904942025371773e1;
  const double q = ((((z + 2.485846490142306297962e1) * z + 1.650270098316988542046e2) * z + 4.328810604912902668951e2) * z +
                    4.853903996359136964868e2) *
                       z +
                   1.945506571482613964390e2;
  return base + ((t * (z * p / q) + t) + tail);
}

}  // namespace clothsim::vector_math
