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
//
// The float version (the lattice kernel's float32 forces, lattice_kernel.h) evaluates the same
// formula with the constants rounded to float: the rational function is well conditioned on its
// interval, so it stays within a few float ulps of atan2 (the same test checks it), and one
// formula serves both precisions.
#pragma once

namespace clothsim::vector_math {

// The angle atan2(y, x) in [0, pi/2] for y >= 0 and x >= 0, not both zero. Branch-free.
//
// With r = min(x, y) / max(x, y) in [0, 1] (never formed: see below):
//   y <= x:  atan(r)                 (reduced with tan(pi/4 + t) when r > 0.66)
//   y >  x:  pi/2 - atan(r)          (reduced with tan(pi/4 - t) when r >= tan(pi/8))
// which are Cephes' three intervals [0, 0.66], (0.66, tan(3 pi/8)], (tan(3 pi/8), inf) for the
// ratio y / x, reached without forming that ratio (it overflows as x -> 0).
template <typename Real>
[[gnu::always_inline]] inline Real atan2_first_quadrant(Real y, Real x) {
  constexpr Real kPiOver2 = static_cast<Real>(1.57079632679489661923);
  constexpr Real kPiOver4 = static_cast<Real>(0.78539816339744830962);
  constexpr Real kTanPiOver8 = static_cast<Real>(0.41421356237309504880);  // 1 / tan(3 pi / 8)
  // pi/2 - kPiOver2 (the part of pi/2 below the double's last bit), Cephes' MOREBITS; in float,
  // the part below float's last bit.
  constexpr Real kPiOver2Tail = static_cast<Real>(1.57079632679489661923 - static_cast<double>(kPiOver2)) +
                                static_cast<Real>(6.123233995736765886130e-17);
  // Cephes' rational approximation atan(t) = t + t z P(z) / Q(z), z = t^2, |t| <= 0.66.
  constexpr Real p4 = static_cast<Real>(-8.750608600031904122785e-1), p3 = static_cast<Real>(-1.615753718733365076637e1),
                 p2 = static_cast<Real>(-7.500855792314704667340e1), p1 = static_cast<Real>(-1.228866684490136173410e2),
                 p0 = static_cast<Real>(-6.485021904942025371773e1);
  constexpr Real q4 = static_cast<Real>(2.485846490142306297962e1), q3 = static_cast<Real>(1.650270098316988542046e2),
                 q2 = static_cast<Real>(4.328810604912902668951e2), q1 = static_cast<Real>(4.853903996359136964868e2),
                 q0 = static_cast<Real>(1.945506571482613964390e2);
  const bool swapped = y > x;
  const Real numerator = swapped ? x : y;
  const Real denominator = swapped ? y : x;
  // Reduce when the ratio r = numerator / denominator exceeds 0.66 (ratio y/x up to
  // tan(3 pi/8)), or, when swapped, tan(pi/8) (ratio y/x below tan(3 pi/8)). Selects of doubles
  // only: GCC 12 fails to vectorise selects between boolean values.
  const Real threshold = swapped ? kTanPiOver8 : static_cast<Real>(0.66);
  const bool reduced = numerator > threshold * denominator;
  const Real sign = swapped ? Real(-1) : Real(1);
  // t = a / b is the argument of the polynomial: r, or (r - 1) / (r + 1) = (n - d) / (n + d)
  // when reduced, negated when swapped (pi/2 - atan).
  const Real a = sign * (reduced ? numerator - denominator : numerator);
  const Real b = reduced ? numerator + denominator : denominator;
  const Real unreduced_base = swapped ? kPiOver2 : Real(0);
  const Real unreduced_tail = swapped ? kPiOver2Tail : Real(0);
  const Real base = reduced ? kPiOver4 : unreduced_base;
  const Real tail = reduced ? Real(0.5) * kPiOver2Tail : unreduced_tail;
  const Real t = a / b;
  const Real z = t * t;
  const Real p = (((p4 * z + p3) * z + p2) * z + p1) * z + p0;
  const Real q = ((((z + q4) * z + q3) * z + q2) * z + q1) * z + q0;
  return base + ((t * (z * p / q) + t) + tail);
}

}  // namespace clothsim::vector_math
