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
// double. tests/forces/test_lattice_kernel.cpp compares it with std::atan2 over the whole range.
#pragma once

namespace clothsim::vector_math {

// The angle atan2(y, x) in [0, pi/2] for y >= 0 and x >= 0, not both zero. Branch-free.
//
// With r = min(x, y) / max(x, y) in [0, 1] (never formed: see below):
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
  // Cephes' rational approximation atan(t) = t + t z P(z) / Q(z), z = t^2, |t| <= 0.66.
  constexpr double p4 = -8.750608600031904122785e-1, p3 = -1.615753718733365076637e1, p2 = -7.500855792314704667340e1,
                   p1 = -1.228866684490136173410e2, p0 = -6.485021904942025371773e1;
  constexpr double q4 = 2.485846490142306297962e1, q3 = 1.650270098316988542046e2, q2 = 4.328810604912902668951e2,
                   q1 = 4.853903996359136964868e2, q0 = 1.945506571482613964390e2;
  const bool swapped = y > x;
  const double numerator = swapped ? x : y;
  const double denominator = swapped ? y : x;
  // Reduce when the ratio r = numerator / denominator exceeds 0.66 (ratio y/x up to
  // tan(3 pi/8)), or, when swapped, tan(pi/8) (ratio y/x below tan(3 pi/8)). Selects of doubles
  // only: GCC 12 fails to vectorise selects between boolean values.
  const double threshold = swapped ? kTanPiOver8 : 0.66;
  const bool reduced = numerator > threshold * denominator;
  const double sign = swapped ? -1.0 : 1.0;
  // t = a / b is the argument of the polynomial: r, or (r - 1) / (r + 1) = (n - d) / (n + d)
  // when reduced, negated when swapped (pi/2 - atan).
  const double a = sign * (reduced ? numerator - denominator : numerator);
  const double b = reduced ? numerator + denominator : denominator;
  const double unreduced_base = swapped ? kPiOver2 : 0.0;
  const double unreduced_tail = swapped ? kPiOver2Tail : 0.0;
  const double base = reduced ? kPiOver4 : unreduced_base;
  const double tail = reduced ? 0.5 * kPiOver2Tail : unreduced_tail;
  const double t = a / b;
  const double z = t * t;
  const double p = (((p4 * z + p3) * z + p2) * z + p1) * z + p0;
  const double q = ((((z + q4) * z + q3) * z + q2) * z + q1) * z + q0;
  return base + ((t * (z * p / q) + t) + tail);
}

}  // namespace clothsim::vector_math
