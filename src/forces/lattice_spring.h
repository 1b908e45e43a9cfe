// The lattice kernel's spring math (lattice_kernel.cpp), in either precision of its forces: a
// small 3-vector of Real, and one radial spring from the unit vectors and inverse lengths of its
// two connectors. Real is double (the default forces) or float (--precision float32, see
// lattice_kernel.h); both are the same formulas, and in double they are exactly the operations
// the kernel did before it took a precision, so the float64 forces did not change by a bit.
//
// Inline and header-only: every function is compiled into the multiversioned loops that call it
// (core/multiversion.h), where it vectorises.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "forces/element.h"
#include "forces/vector_math.h"

namespace clothsim::lattice_spring {

// Three Reals, with the operations of Vec3 (core/vec3.h) in the same order of evaluation.
template <typename Real>
struct Vector {
  Real x;
  Real y;
  Real z;
  [[gnu::always_inline]] constexpr Vector& operator+=(const Vector& o) {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
};
template <typename Real>
[[gnu::always_inline]] constexpr Vector<Real> operator+(const Vector<Real>& a, const Vector<Real>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <typename Real>
[[gnu::always_inline]] constexpr Vector<Real> operator-(const Vector<Real>& a, const Vector<Real>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <typename Real>
[[gnu::always_inline]] constexpr Vector<Real> operator-(const Vector<Real>& a) {
  return {-a.x, -a.y, -a.z};
}
template <typename Real>
[[gnu::always_inline]] constexpr Vector<Real> operator*(Real s, const Vector<Real>& a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <typename Real>
[[gnu::always_inline]] constexpr Real dot(const Vector<Real>& a, const Vector<Real>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <typename Real>
[[gnu::always_inline]] constexpr Vector<Real> cross(const Vector<Real>& a, const Vector<Real>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// Where the positions stop defining a radial spring's bending plane (element.h, "The singular
// configurations"), per precision.
//   sine     below this sin(theta) the plane is taken from the motion. In double it is the
//            element's kSingularSine, 1e-12: the unit vectors are good to about 1e-16, so the
//            plane's direction w / sin(theta) is good to 1e-4 there. In float the unit vectors
//            are good to about 1e-7, and the same 1e-4 is reached at sin(theta) = 1e-3.
//   opening  an opening rate below this fraction of the turning rates is rounding, with no
//            direction (element::resolve_singular_directions): 1e-12 in double, about 100 float
//            ulps in float.
template <typename Real>
struct SingularLimits;
template <>
struct SingularLimits<double> {
  static constexpr double sine = element::kSingularSine;
  static constexpr double opening = element::kSingularSine;
};
template <>
struct SingularLimits<float> {
  static constexpr float sine = 1e-6f;
  static constexpr float opening = 1e-5f;
};

// The fade of the radial springs on an arm of length `length` with fade length `fade_length` (m):
// element::arm_fade's quintic, in the same order of operations, as selects so that it vectorises.
template <typename Real>
struct Fade {
  Real value = 1;  // phi(l / f)
  Real slope = 0;  // d phi / d l, 1/m
};

template <typename Real>
[[gnu::always_inline]] inline Fade<Real> arm_fade(Real length, Real fade_length) {
  const Real one = 1;
  const bool inside = length < fade_length;
  const Real s = inside ? length / fade_length : one;
  const Real r = one - s;
  const Real value =
      s * s * s * (Real(element::kFadeCubic) + s * (Real(element::kFadeQuartic) + s * Real(element::kFadeQuintic)));
  const Real slope = Real(element::kFadeSlope) * s * s * r * r / (inside ? fade_length : one);
  return {inside ? value : one, inside ? slope : Real(0)};
}

// One radial spring between the connectors centre->b and centre->c, from their unit vectors and
// inverse lengths (0: no such connector), their fades (phi and d phi / d l, from arm_fade) and
// the relative velocities v_b - v_a, v_c - v_a. The formulas are those of element::radial_force,
// rearranged to multiply by 1/length and 1/sin(theta) once and to scale w = sin(theta) p instead
// of forming p. A singular spring (sin(theta) < SingularLimits::sine) gets meaningless values
// from the kResolveSingular = false version, which only reports it through `singular`; the
// caller then recomputes it with the true version, which takes the bending plane from the motion
// like element::resolve_singular_directions. kFade = false leaves the fade out: for springs whose
// arms are all outside it (fade 1, slope 0), where it changes nothing, bit for bit.
template <typename Real>
struct RadialResult {
  Vector<Real> on_b;
  Vector<Real> on_c;
  Real power = 0;
  Real singular = 0;  // > 0 if the spring is singular (a Real: GCC vectorises it better than a bool)
};

template <typename Real, bool kResolveSingular, bool kFade>
[[gnu::always_inline]] inline RadialResult<Real> radial_spring(const Vector<Real>& ub, Real inverse_b,
                                                               const Fade<Real>& fade_b, const Vector<Real>& uc,
                                                               Real inverse_c, const Fade<Real>& fade_c,
                                                               const Vector<Real>& rb, const Vector<Real>& rc,
                                                               Real unfaded_stiffness, Real unfaded_damping,
                                                               Real rest_angle) {
  using Limits = SingularLimits<Real>;
  const Real zero = 0;
  const Real one = 1;
  const bool exists = std::min(inverse_b, inverse_c) > zero;
  // The faded energy's force (element::radial_force): the spring's coefficients times
  // phi_b phi_c (1 exactly outside the fade, so the products keep their bits), then the pull
  // along each arm.
  const Real fade = kFade ? fade_b.value * fade_c.value : one;
  const Real stiffness = kFade ? fade * unfaded_stiffness : unfaded_stiffness;
  const Real damping = kFade ? fade * unfaded_damping : unfaded_damping;
  const Vector<Real> n = cross(ub, uc);
  const Real cosine = dot(ub, uc);
  const Real sine = std::sqrt(dot(n, n));
  const Vector<Real> wb = cross(n, ub);  // sin(theta) p_b
  const Vector<Real> wc = cross(uc, n);  // sin(theta) p_c
  const Real inverse_sine = one / sine;
  const bool obtuse = cosine < zero;
  RadialResult<Real> out;
  out.singular = exists ? Limits::sine - sine : -one;
  // theta (acute) or pi - theta (obtuse), and (that angle) / sin(theta) without cancellation.
  const Real angle = vector_math::atan2_first_quadrant(sine, std::abs(cosine));
  const Real angle2 = angle * angle;
  // element::x_over_sin's series and its end, as a select.
  const Real series = one + angle2 * (Real(element::kXOverSinSecond) + angle2 * Real(element::kXOverSinFourth));
  const Real ratio = angle < Real(element::kXOverSinSeriesEnd) ? series : angle * inverse_sine;
  const Real smooth = obtuse ? -ratio : ratio;
  const Real constant = obtuse ? std::numbers::pi_v<Real> - rest_angle : -rest_angle;
  const Real kb = stiffness * inverse_b;
  const Real kc = stiffness * inverse_c;
  // p = w / sin(theta) is parallel to w, so every force along p is a multiple of w:
  //   f_b = [k/l_b (A + B / sin) + torque (-1/(l_b sin))] w_b,  dtheta/dx_b = -w_b / (l_b sin).
  const Real gradient_b = -inverse_b * inverse_sine;
  const Real gradient_c = -inverse_c * inverse_sine;
  Real angle_rate = gradient_b * dot(wb, rb) + gradient_c * dot(wc, rc);
  Real torque = -damping * angle_rate;
  const Real elastic = smooth + constant * inverse_sine;
  Vector<Real> fb = (kb * elastic + torque * gradient_b) * wb;
  Vector<Real> fc = (kc * elastic + torque * gradient_c) * wc;
  if constexpr (kResolveSingular) {
    // Singular: the bending plane from the motion (element::resolve_singular_directions).
    // Computed for every spring and selected, so that this loop vectorises too; non-singular
    // springs keep exactly the values above.
    const Vector<Real> turn_b = inverse_b * (rb - dot(rb, ub) * ub);
    const Vector<Real> turn_c = inverse_c * (rc - dot(rc, uc) * uc);
    const Vector<Real> opening = obtuse ? turn_b + turn_c : turn_c - turn_b;
    const Real rate = std::sqrt(dot(opening, opening));
    // Rounding-sized openings have no direction (element::resolve_singular_directions).
    const Real turning = inverse_b * std::sqrt(dot(rb, rb)) + inverse_c * std::sqrt(dot(rc, rc));
    const Real inverse_rate = rate > Limits::opening * turning ? one / rate : zero;
    const Vector<Real> pb = inverse_rate * opening;
    const Vector<Real> pc = obtuse ? pb : -pb;
    Vector<Real> singular_fb = kb * (smooth * wb + constant * pb);
    Vector<Real> singular_fc = kc * (smooth * wc + constant * pc);
    const Vector<Real> gb = -inverse_b * pb;  // dtheta/dx_b
    const Vector<Real> gc = -inverse_c * pc;
    const Real singular_rate = dot(gb, rb) + dot(gc, rc);
    const Real singular_torque = -damping * singular_rate;
    singular_fb += singular_torque * gb;
    singular_fc += singular_torque * gc;
    const bool use = out.singular > zero;
    fb = {use ? singular_fb.x : fb.x, use ? singular_fb.y : fb.y, use ? singular_fb.z : fb.z};
    fc = {use ? singular_fc.x : fc.x, use ? singular_fc.y : fc.y, use ? singular_fc.z : fc.z};
    angle_rate = use ? singular_rate : angle_rate;
    torque = use ? singular_torque : torque;
  }
  if constexpr (kFade) {
    // The product rule's pull, -E phi_c phi_b' u_b on b (likewise on c), selected only inside
    // the fade so that outside it the forces keep their bits (adding a zero could turn -0 into +0).
    const Real theta = obtuse ? std::numbers::pi_v<Real> - angle : angle;
    const Real departure = theta - rest_angle;
    const Real energy = Real(0.5) * unfaded_stiffness * departure * departure;
    const Real pull_b = energy * fade_c.value * fade_b.slope;
    const Real pull_c = energy * fade_b.value * fade_c.slope;
    const bool fading = fade < one;
    fb = {fading ? fb.x - pull_b * ub.x : fb.x, fading ? fb.y - pull_b * ub.y : fb.y,
          fading ? fb.z - pull_b * ub.z : fb.z};
    fc = {fading ? fc.x - pull_c * uc.x : fc.x, fading ? fc.y - pull_c * uc.y : fc.y,
          fading ? fc.z - pull_c * uc.z : fc.z};
  }
  out.on_b = {exists ? fb.x : zero, exists ? fb.y : zero, exists ? fb.z : zero};
  out.on_c = {exists ? fc.x : zero, exists ? fc.y : zero, exists ? fc.z : zero};
  out.power = exists ? torque * angle_rate : zero;
  return out;
}

}  // namespace clothsim::lattice_spring
