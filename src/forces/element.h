// Element math: force, energy and damping power of one connector spring or one radial spring, as
// pure functions of plain values. No model, no arrays: each function is unit-tested against
// finite differences of its energy (tests/forces/test_element.cpp). The functions themselves are
// in element_math.inc, written in the subset of C++ and GLSL the two share, which the Vulkan
// compute shaders include as well (src/gpu/shaders/element_math.glsl): one source of truth for
// the CPU and the GPU, held together by tests/gpu/test_element_forces.cpp. This header includes
// it in double precision, spelled by core/shared_text.h.
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
//
// Vanishing arms. The energy above and its damping are multiplied by phi(l_b / f_b) phi(l_c / f_c),
// which is 1 while both arms are at least their fade length f (half the connector's original
// length) and falls smoothly to 0 as an arm vanishes, so that a collapsing connector does not
// make its radial springs' forces grow as 1 / length (element_math.inc, kRadialFadeFraction).
#pragma once

#include <cmath>
#include <numbers>

#include "core/shared_text.h"
#include "core/vec3.h"

namespace clothsim::element {

using Real = double;
// The general element path keeps libm's atan2 rather than the shared arctangent of
// forces/arctangent.inc that the lattice kernel and the shaders use: every run's energy.csv sums
// radial_energy over all springs, and the crease law measures angles with radial_angle, so a
// switch would move those outputs in their last bits (docs/architecture.md, "Shared laws").
using std::atan2;

#include "forces/element_math.inc"

}  // namespace clothsim::element
