// Element math: force, energy and damping power of one connector spring or one radial spring, as
// pure functions of plain values. No model, no arrays: each function is unit-tested against
// finite differences of its energy (tests/forces/test_element.cpp) and can be ported line for
// line to a shader.
//
// Connector spring between particles a and b (rest length L, stiffness k, damping c):
//   e = x_b - x_a, l = |e|, u = e / l
//   f_a = (k (l - L) + c (v_b - v_a).u) u,   f_b = -f_a,   E = 1/2 k (l - L)^2
//
// Radial spring at particle a between its connectors a->b and a->c (rest angle theta0, stiffness
// k in N m/rad, damping c in N m s/rad). theta is the smallest angle between the connectors,
// theta = atan2(|e_b x e_c|, e_b . e_c) in [0, pi], and the spring is the energy
//   E = 1/2 k (theta - theta0)^2
// with damping along the same gradient (docs/model.md derives both from the paper's torque
// balance):
//   tau = -k (theta - theta0) - c dtheta/dt,   f_j = tau dtheta/dx_j  for j in {a, b, c}
//   dtheta/dx_b = -p_b / |e_b|, p_b the unit vector perpendicular to e_b, in the plane of the two
//   connectors, pointing towards e_c; likewise for c; dtheta/dx_a = -(dtheta/dx_b + dtheta/dx_c).
//
// The singular configurations. With unit vectors u_b, u_c, let n = u_b x u_c (|n| = sin theta)
// and w_b = n x u_b = u_c - (u_c . u_b) u_b, so that p_b = w_b / sin theta. The elastic force is
//   f_b = k (theta - theta0) p_b / |e_b| = (k / |e_b|) ((theta - theta0) / sin theta) w_b,
// and the ratio is split into a part that is smooth through the singular angle plus a constant
// times the unit direction:
//   theta <= pi/2:  (theta - theta0)/sin theta = theta/sin theta            - theta0 / sin theta
//   theta >  pi/2:  (theta - theta0)/sin theta = -delta/sin delta + (pi - theta0) / sin theta,
//                   delta = pi - theta = atan2(|n|, -u_b . u_c), computed without cancellation
// x/sin x is evaluated by its series near 0. So f_b = (k/|e_b|) (A w_b + B p_b) with A smooth.
// When theta0 equals the singular angle (180 degrees for opposite springs, the paper's case),
// B = 0 and the force tends smoothly to -k w_b/|e_b| -> 0 as the sheet straightens: no division
// by a tiny sine. Otherwise B != 0 and E has a cone point there: the force keeps its magnitude
// k |theta - theta0| / |e_b| while its direction p_b depends on how the configuration is
// approached. Below sin theta = kSingularSine the positions no longer define that direction, and
// the element takes it from the motion instead: the plane into which the relative velocities
// open the configuration (resolve_singular_directions), which makes the force the one-sided limit
// along the trajectory. Damping uses the same directions. docs/model.md discusses the choice.
#pragma once

#include <cmath>
#include <numbers>

#include "core/vec3.h"

namespace clothsim::element {

// Below this sine of the angle between two connectors, the plane of the pair is undefined.
inline constexpr double kSingularSine = 1e-12;

// ---------------------------------------------------------------------------------------------
// Connector springs

struct ConnectorForce {
  Vec3 force_on_a;             // N; the force on b is -force_on_a
  double damping_power = 0.0;  // W, power of the damping force (never positive)
};

inline ConnectorForce connector_force(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb,
                                      double rest_length, double stiffness, double damping) {
  const Vec3 e = xb - xa;
  const double length = norm(e);
  if (!(length > 0.0)) return {};  // coincident particles: no direction, no force
  const Vec3 u = e / length;
  const double extension_rate = dot(vb - va, u);
  const double tension = stiffness * (length - rest_length) + damping * extension_rate;
  return {tension * u, -damping * extension_rate * extension_rate};
}

inline double connector_energy(const Vec3& xa, const Vec3& xb, double rest_length, double stiffness) {
  const double extension = norm(xb - xa) - rest_length;
  return 0.5 * stiffness * extension * extension;
}

// ---------------------------------------------------------------------------------------------
// Radial springs

// x / sin(x) for x in [0, pi/2], given sin(x): the series 1 + x^2/6 + 7 x^4/360 near 0 (its
// next term, 31 x^6/15120, is below 1e-24 for x < 1e-4), the plain quotient elsewhere.
inline double x_over_sin(double x, double sine) {
  if (x < 1e-4) {
    const double x2 = x * x;
    return 1.0 + x2 * (1.0 / 6.0 + x2 * (7.0 / 360.0));
  }
  return x / sine;
}

// Angle between two connectors and the gradient of that angle.
struct RadialGeometry {
  double angle = 0.0;       // theta in [0, pi], rad
  Vec3 unit_b, unit_c;      // u_b = e_b / |e_b|, u_c = e_c / |e_c|
  Vec3 w_b, w_c;            // n x u_b and u_c x n, of length sin(theta)
  Vec3 direction_b;         // p_b: unit, perpendicular to e_b in the plane, towards e_c (zero if undefined)
  Vec3 direction_c;         // p_c: likewise for e_c, towards e_b
  double length_b = 0.0;    // |e_b|, m
  double length_c = 0.0;    // |e_c|, m
  double sine = 0.0;        // sin(theta)
  bool obtuse = false;      // theta > pi/2
  double delta = 0.0;       // pi - theta, accurate near pi; computed only when obtuse
  bool singular = false;    // sin(theta) below kSingularSine: p_b and p_c not defined by positions
  bool degenerate = false;  // a zero-length connector: no angle at all

  Vec3 gradient_b() const { return -(1.0 / length_b) * direction_b; }  // dtheta/dx_b, 1/m
  Vec3 gradient_c() const { return -(1.0 / length_c) * direction_c; }  // dtheta/dx_c, 1/m
};

inline RadialGeometry radial_geometry(const Vec3& xa, const Vec3& xb, const Vec3& xc) {
  RadialGeometry g;
  const Vec3 eb = xb - xa;
  const Vec3 ec = xc - xa;
  g.length_b = norm(eb);
  g.length_c = norm(ec);
  if (!(g.length_b > 0.0) || !(g.length_c > 0.0)) {
    g.degenerate = g.singular = true;
    return g;
  }
  g.unit_b = eb / g.length_b;
  g.unit_c = ec / g.length_c;
  const Vec3 n = cross(g.unit_b, g.unit_c);
  const double cosine = dot(g.unit_b, g.unit_c);
  g.sine = norm(n);
  g.angle = std::atan2(g.sine, cosine);
  g.obtuse = cosine < 0.0;
  // pi - theta straight from the geometry: subtracting from pi would lose the digits that
  // matter near a straight configuration.
  if (g.obtuse) g.delta = std::atan2(g.sine, -cosine);
  g.w_b = cross(n, g.unit_b);
  g.w_c = cross(g.unit_c, n);
  g.singular = g.sine < kSingularSine;
  if (!g.singular) {
    g.direction_b = g.w_b / g.sine;
    g.direction_c = g.w_c / g.sine;
  }
  return g;
}

// At an exactly straight or folded configuration the plane of the two connectors, and with it
// p_b and p_c, is not defined by the positions. The motion defines it: the configuration opens
// into the plane its relative velocities point to, and taking p_b, p_c from there gives the
// one-sided limit of the force along the trajectory. The force is then continuous in time
// through the singular point (a flat sheet started with any velocity, for instance), which the
// error control of an adaptive integrator needs. With no transverse relative motion the
// directions stay zero (the minimum-norm subgradient).
inline void resolve_singular_directions(RadialGeometry& g, const Vec3& va, const Vec3& vb, const Vec3& vc) {
  if (!g.singular || g.degenerate) return;
  // Rates of change of the unit vectors u_b and u_c, 1/s.
  const Vec3 rb = vb - va;
  const Vec3 rc = vc - va;
  const Vec3 turn_b = (rb - dot(rb, g.unit_b) * g.unit_b) / g.length_b;
  const Vec3 turn_c = (rc - dot(rc, g.unit_c) * g.unit_c) / g.length_c;
  // Straight (u_c = -u_b): the bend grows along turn_b + turn_c, and p_b = p_c point that way.
  // Folded (u_c = u_b): the angle opens along turn_c - turn_b; p_b points that way, p_c opposite.
  const Vec3 opening = g.obtuse ? turn_b + turn_c : turn_c - turn_b;
  const double rate = norm(opening);
  // Motion along the springs leaves rounding in turn_b and turn_c, of order 1e-16 of the turning
  // rates: an opening that small has no direction (normalised, it would point anywhere, even
  // along the springs, and the damping would push along them).
  if (!(rate > kSingularSine * (norm(rb) / g.length_b + norm(rc) / g.length_c))) return;
  g.direction_b = opening / rate;
  g.direction_c = g.obtuse ? g.direction_b : -g.direction_b;
}

struct RadialForce {
  Vec3 force_on_b;             // N
  Vec3 force_on_c;             // N; the force on the centre is -(force_on_b + force_on_c)
  double damping_power = 0.0;  // W (never positive)
};

// The elastic force k (theta - theta0) p_j / |e_j| on b and c, evaluated without dividing by a
// small sine (see the file comment).
inline void add_radial_elastic_force(const RadialGeometry& g, double rest_angle, double stiffness, RadialForce& out) {
  if (g.degenerate) return;
  double smooth = 0.0;    // A: multiplies w
  double constant = 0.0;  // B: multiplies p = w / sin(theta)
  if (!g.obtuse) {
    smooth = x_over_sin(g.angle, g.sine);
    constant = -rest_angle;
  } else {
    smooth = -x_over_sin(g.delta, g.sine);
    constant = std::numbers::pi - rest_angle;
  }
  out.force_on_b += (stiffness / g.length_b) * (smooth * g.w_b + constant * g.direction_b);
  out.force_on_c += (stiffness / g.length_c) * (smooth * g.w_c + constant * g.direction_c);
}

inline RadialForce radial_force(const Vec3& xa, const Vec3& xb, const Vec3& xc, const Vec3& va, const Vec3& vb,
                                const Vec3& vc, double rest_angle, double stiffness, double damping) {
  RadialGeometry g = radial_geometry(xa, xb, xc);
  resolve_singular_directions(g, va, vb, vc);
  RadialForce out;
  add_radial_elastic_force(g, rest_angle, stiffness, out);
  if (damping != 0.0 && !g.degenerate) {
    const Vec3 gradient_b = g.gradient_b();
    const Vec3 gradient_c = g.gradient_c();
    const double angle_rate = dot(gradient_b, vb - va) + dot(gradient_c, vc - va);
    const double damping_torque = -damping * angle_rate;
    out.force_on_b += damping_torque * gradient_b;
    out.force_on_c += damping_torque * gradient_c;
    out.damping_power = damping_torque * angle_rate;
  }
  return out;
}

inline double radial_angle(const Vec3& xa, const Vec3& xb, const Vec3& xc) {
  return std::atan2(norm(cross(xb - xa, xc - xa)), dot(xb - xa, xc - xa));
}

inline double radial_energy(const Vec3& xa, const Vec3& xb, const Vec3& xc, double rest_angle, double stiffness) {
  const double d = radial_angle(xa, xb, xc) - rest_angle;
  return 0.5 * stiffness * d * d;
}

}  // namespace clothsim::element
