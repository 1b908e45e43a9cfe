// Element Jacobians for implicit integration: the derivatives of the element forces of element.h
// with respect to positions and velocities, as pure functions of plain values (tested against
// finite differences in tests/forces/test_element_jacobian.cpp). Their factors are shared text,
// forces/element_jacobian.inc, which the Vulkan backend's implicit Euler compiles too; this header
// builds the CPU's 3x3 blocks from them.
//
// Sign convention. Implicit Euler needs K = -df/dx (the stiffness matrix, the Hessian of the
// elastic energy) and C = -df/dv (the damping matrix), because the system it solves is
// M + h C + h^2 K (integrators/implicit_euler.h). Both are returned negated like that, and the
// approximations below keep them symmetric positive semi-definite, so that the system matrix is
// symmetric positive definite and conjugate gradients applies.
//
// Connector springs (exact, with one optional clamp). With e = x_b - x_a, l = |e|, u = e/l:
//   -df_a/dx_a = K_e = k [u u^T + (1 - L/l) (I - u u^T)],  -df_a/dx_b = -K_e, and so on;
//   -df_a/dv_a = C_e = c u u^T.
// The second term is the geometric stiffness: a stretched spring resists sideways motion with
// stiffness tension / length. Compressed (l < L) it is negative and K_e indefinite, which is the
// buckling instability of a compressed spring; a Newton step through it can diverge and conjugate
// gradients needs a definite matrix. Like Choi and Ko ("Stable but responsive cloth", SIGGRAPH
// 2002, sec. 4) and most implicit cloth solvers since, we clamp (1 - L/l) at zero in compression
// (`clamp_compression`); the force itself stays exact, only the step's linearisation changes.
//
// Radial springs (positive semi-definite approximation). E = 1/2 k (theta - theta0)^2 has the
// Hessian k g g^T + k (theta - theta0) d^2theta/dx^2, g = dtheta/dx the 9-vector of element.h.
// The first term is the Gauss-Newton part, positive semi-definite, and we keep it as is. The
// curvature term is indefinite in general; we keep only the part of it that the lattice cannot do
// without, the out-of-plane one:
//   * In the plane of the two connectors, the curvature term is dropped (Gauss-Newton).
//   * Out of the plane, theta has no gradient (a mirror symmetry through the plane), so the
//     Gauss-Newton part is zero there, and for a nearly straight opposite spring (theta0 = pi)
//     the curvature term is the whole bending stiffness across the plane: without it a flat
//     sheet would have no bending stiffness in the Jacobian at all, and a step of 1/60 s on
//     cotton becomes unstable. Displacing b, c and the centre by eps_j along the plane's unit
//     normal n tilts the connectors by alpha_b = (eps_b - eps_a)/|e_b|, alpha_c likewise, and
//     changes theta at second order by 1/2 alpha^T Q alpha with
//       Q = (1/sin theta) [[cos theta, -1], [-1, cos theta]],
//     whose eigenvalues are -tan(theta/2) along (1, 1) (both connectors tilt the same way, which
//     bends a straight pair) and cot(theta/2) along (1, -1). The energy's out-of-plane block is
//     k (theta - theta0) Q; we take its eigenvalues clamped at zero,
//       lambda_1 = max(0, k (theta0 - theta) tan(theta/2)),  lambda_2 = max(0, k (theta - theta0) cot(theta/2)),
//     which is exact where they are non-negative (an opposite spring with theta > pi/2, an
//     adjacent spring opening past its rest angle) and positive semi-definite always.
//   * At an exactly straight pair (sin theta below kSingularSine) with theta0 = pi, the plane is
//     undefined and the energy is smooth: its Hessian is k s s^T (x) (I - u u^T), s = (-(1/|e_b| +
//     1/|e_c|), 1/|e_b|, 1/|e_c|) over (centre, b, c), the limit of the two parts above. Other
//     singular configurations (folded pairs, cone points of theta0 != pi) keep only the
//     Gauss-Newton part along the direction the motion selects (resolve_singular_directions).
// Damping: f = -c (g . v) g gives -df/dv = c g g^T exactly (g depends on positions only).
//
// The fade of vanishing arms (element_math.inc, kRadialFadeFraction) multiplies the energy and
// the damping by phi = phi_b phi_c, which depends on positions only. The damping Jacobian
// phi c g g^T stays exact. The stiffness is taken as phi times the approximation above: the
// Hessian of phi E also has the terms dphi (dE)^T + dE dphi^T + E d^2phi, which vanish with
// theta - theta0 (E and dE do), so at the rest angle the faded K = phi k g g^T is exact; away
// from it they are dropped like the in-plane curvature term (they are indefinite too), which
// only slows Newton's convergence inside the fade, not what the step converges to.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "core/mat3.h"
#include "core/vec3.h"
#include "forces/element.h"

namespace clothsim::element {

using std::max;
#include "forces/element_jacobian.inc"

// ---------------------------------------------------------------------------------------------
// Connector springs

struct ConnectorJacobian {
  Mat3 stiffness;  // K_e = -df_a/dx_a = df_a/dx_b, N/m (symmetric)
  Mat3 damping;    // C_e = -df_a/dv_a = df_a/dv_b = c u u^T, N s/m (symmetric)
};

inline ConnectorJacobian connector_jacobian(const Vec3& xa, const Vec3& xb, double rest_length, double stiffness,
                                            double damping, bool clamp_compression) {
  const ConnectorLinearization factors =
      connector_linearization(xa, xb, rest_length, stiffness, damping, clamp_compression);
  const Mat3 along = outer(factors.direction, factors.direction);
  ConnectorJacobian out;
  out.stiffness = factors.along * along + factors.across * (Mat3::identity() - along);
  out.damping = factors.damping * along;
  return out;
}

// ---------------------------------------------------------------------------------------------
// Radial springs

// Local element indices: 0 the centre particle, 1 particle b, 2 particle c.
struct RadialJacobian {
  std::array<Vec3, 3> gradient;     // g = dtheta/dx of the centre, b, c, 1/m (as used by the force)
  double in_plane_stiffness = 0.0;  // coefficient of g g^T in K, N m/rad (k, or 0 if folded into `transverse`)
  double damping = 0.0;             // coefficient of g g^T in C, N m s/rad
  Mat3 transverse;                  // P: n n^T, or I - u u^T at a straight singular pair
  std::array<std::array<double, 3>, 3> transverse_coupling{};  // mu_ij, N m: block (i, j) of K gets mu_ij P

  // Block (i, j) of K = -df/dx (approximate, positive semi-definite as a whole), N/m.
  Mat3 stiffness_block(int i, int j) const {
    const auto a = static_cast<std::size_t>(i);
    const auto b = static_cast<std::size_t>(j);
    return in_plane_stiffness * outer(gradient[a], gradient[b]) + transverse_coupling[a][b] * transverse;
  }
  // Block (i, j) of C = -df/dv (exact), N s/m.
  Mat3 damping_block(int i, int j) const {
    return damping * outer(gradient[static_cast<std::size_t>(i)], gradient[static_cast<std::size_t>(j)]);
  }
};

// The Jacobians of radial_force() at the same arguments.
inline RadialJacobian radial_jacobian(const Vec3& xa, const Vec3& xb, const Vec3& xc, const Vec3& va, const Vec3& vb,
                                      const Vec3& vc, double rest_angle, double stiffness, double damping,
                                      double fade_length_b, double fade_length_c) {
  const RadialLinearization factors =
      radial_linearization(xa, xb, xc, va, vb, vc, rest_angle, stiffness, damping, fade_length_b, fade_length_c);
  RadialJacobian out;
  out.gradient = {factors.gradient_a, factors.gradient_b, factors.gradient_c};
  out.in_plane_stiffness = factors.in_plane_stiffness;
  out.damping = factors.damping;
  const Vec3& axis = factors.transverse_axis;
  out.transverse = factors.straight ? Mat3::identity() - outer(axis, axis) : outer(axis, axis);
  const std::array<double, 3> s = {factors.sum_tilt.x, factors.sum_tilt.y, factors.sum_tilt.z};
  const std::array<double, 3> d = {factors.difference_tilt.x, factors.difference_tilt.y, factors.difference_tilt.z};
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < 3; ++j) {
      out.transverse_coupling[i][j] = factors.equal_coupling * s[i] * s[j] + factors.opposite_coupling * d[i] * d[j];
    }
  }
  return out;
}

}  // namespace clothsim::element
