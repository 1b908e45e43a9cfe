// Element Jacobians for implicit integration: the derivatives of the element forces of element.h
// with respect to positions and velocities, as pure functions of plain values (tested against
// finite differences in tests/forces/test_element_jacobian.cpp).
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

#include <array>
#include <cmath>
#include <numbers>

#include "core/mat3.h"
#include "core/vec3.h"
#include "forces/element.h"

namespace clothsim::element {

// ---------------------------------------------------------------------------------------------
// Connector springs

struct ConnectorJacobian {
  Mat3 stiffness;  // K_e = -df_a/dx_a = df_a/dx_b, N/m (symmetric)
  Mat3 damping;    // C_e = -df_a/dv_a = df_a/dv_b = c u u^T, N s/m (symmetric)
};

inline ConnectorJacobian connector_jacobian(const Vec3& xa, const Vec3& xb, double rest_length, double stiffness,
                                            double damping, bool clamp_compression) {
  const Vec3 e = xb - xa;
  const double length = norm(e);
  if (!(length > 0.0)) return {};  // coincident particles: no direction, as in connector_force
  const Vec3 u = e / length;
  const Mat3 along = outer(u, u);
  double geometric = 1.0 - rest_length / length;
  if (clamp_compression && geometric < 0.0) geometric = 0.0;
  ConnectorJacobian out;
  out.stiffness = stiffness * along + (stiffness * geometric) * (Mat3::identity() - along);
  out.damping = damping * along;
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

// x / tan(x) for x in [0, pi/2): the series 1 - x^2/3 - x^4/45 near 0 (next term 2 x^6/945).
inline double x_over_tan(double x) {
  if (x < 1e-4) {
    const double x2 = x * x;
    return 1.0 - x2 * (1.0 / 3.0 + x2 * (1.0 / 45.0));
  }
  return x / std::tan(x);
}

// Eigenvalues of the out-of-plane block of the energy Hessian, clamped at zero (file comment):
// first along equal tilts of both connectors, second along opposite tilts. N m.
inline std::array<double, 2> radial_transverse_eigenvalues(const RadialGeometry& g, double rest_angle,
                                                           double stiffness) {
  double along_equal = 0.0;
  double along_opposite = 0.0;
  if (!g.obtuse) {
    // tan(theta/2) <= 1 here; cot(theta/2) is large near theta = 0 and written as (x/tan x) / x.
    along_equal = stiffness * (rest_angle - g.angle) * std::tan(0.5 * g.angle);
    if (g.angle > rest_angle) {
      along_opposite = stiffness * (1.0 - rest_angle / g.angle) * 2.0 * x_over_tan(0.5 * g.angle);
    }
  } else {
    // With delta = pi - theta (accurate near straight), tan(theta/2) = cot(delta/2).
    const double rest_delta = std::numbers::pi - rest_angle;
    if (g.delta > rest_delta) {
      along_equal = stiffness * (1.0 - rest_delta / g.delta) * 2.0 * x_over_tan(0.5 * g.delta);
    }
    along_opposite = stiffness * (rest_delta - g.delta) * std::tan(0.5 * g.delta);
  }
  return {std::max(0.0, along_equal), std::max(0.0, along_opposite)};
}

// The Jacobians of radial_force() at the same arguments.
inline RadialJacobian radial_jacobian(const Vec3& xa, const Vec3& xb, const Vec3& xc, const Vec3& va, const Vec3& vb,
                                      const Vec3& vc, double rest_angle, double stiffness, double damping,
                                      double fade_length_b, double fade_length_c) {
  RadialGeometry g = radial_geometry(xa, xb, xc);
  resolve_singular_directions(g, va, vb, vc);
  RadialJacobian out;
  if (g.degenerate) return out;
  // The fade scales both coefficients (file comment); 1 exactly outside it.
  const double fade = arm_fade(g.length_b, fade_length_b).value * arm_fade(g.length_c, fade_length_c).value;
  stiffness *= fade;
  damping *= fade;
  out.gradient[1] = radial_gradient_b(g);
  out.gradient[2] = radial_gradient_c(g);
  out.gradient[0] = -(out.gradient[1] + out.gradient[2]);
  out.in_plane_stiffness = stiffness;
  out.damping = damping;

  // Tilt rates: alpha_b = s_b . (eps_a, eps_b, eps_c), alpha_c = s_c . eps.
  const std::array<double, 3> tilt_b = {-1.0 / g.length_b, 1.0 / g.length_b, 0.0};
  const std::array<double, 3> tilt_c = {-1.0 / g.length_c, 0.0, 1.0 / g.length_c};
  if (g.singular) {
    if (g.obtuse && rest_angle == std::numbers::pi) {
      // Straight pair at its rest angle: isotropic bending stiffness across the line.
      out.in_plane_stiffness = 0.0;
      out.transverse = Mat3::identity() - outer(g.unit_b, g.unit_b);
      for (std::size_t i = 0; i < 3; ++i) {
        for (std::size_t j = 0; j < 3; ++j) {
          out.transverse_coupling[i][j] = stiffness * (tilt_b[i] + tilt_c[i]) * (tilt_b[j] + tilt_c[j]);
        }
      }
    }
    return out;
  }
  const Vec3 normal = cross(g.unit_b, g.unit_c) / g.sine;
  out.transverse = outer(normal, normal);
  const std::array<double, 2> lambda = radial_transverse_eigenvalues(g, rest_angle, stiffness);
  // mu = lambda_1 q1 q1^T + lambda_2 q2 q2^T with q1,2 = (s_b +- s_c)/sqrt(2).
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < 3; ++j) {
      out.transverse_coupling[i][j] = 0.5 * (lambda[0] * (tilt_b[i] + tilt_c[i]) * (tilt_b[j] + tilt_c[j]) +
                                             lambda[1] * (tilt_b[i] - tilt_c[i]) * (tilt_b[j] - tilt_c[j]));
    }
  }
  return out;
}

}  // namespace clothsim::element
