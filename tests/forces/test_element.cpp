// Element forces against the negative gradient of the element energy (central differences), the
// damping terms against their definitions, the singular straight and folded configurations, and
// the fade of radial springs whose arm vanishes.
#include "forces/element.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "test_support.h"

namespace clothsim {
namespace {

using testing::numerical_gradient;
using testing::TestRandom;

constexpr double kPi = std::numbers::pi;

void expect_vec_near(const Vec3& actual, const Vec3& expected, double tolerance, const char* what) {
  EXPECT_NEAR(actual.x, expected.x, tolerance) << what;
  EXPECT_NEAR(actual.y, expected.y, tolerance) << what;
  EXPECT_NEAR(actual.z, expected.z, tolerance) << what;
}

// ---- connector springs ----------------------------------------------------------------------

TEST(ConnectorElement, ForceIsMinusEnergyGradient) {
  TestRandom random(1);
  for (int trial = 0; trial < 100; ++trial) {
    const Vec3 xa = random.vector(-1, 1);
    const Vec3 xb = random.vector(-1, 1);
    const double rest = random.uniform(0.1, 2.0);
    const double k = random.uniform(1, 100);
    const element::ConnectorForce f = element::connector_force(xa, xb, {}, {}, rest, k, 0.0);
    const Vec3 grad_a =
        numerical_gradient([&](const Vec3& x) { return element::connector_energy(x, xb, rest, k); }, xa, 1e-6);
    const double scale = 1e-6 * (1 + norm(f.force_on_a));
    expect_vec_near(f.force_on_a, -grad_a, scale, "f_a = -dE/dx_a");
    EXPECT_EQ(f.damping_power, 0.0);
  }
}

TEST(ConnectorElement, DampingActsAlongTheSpringAndDissipates) {
  TestRandom random(2);
  for (int trial = 0; trial < 50; ++trial) {
    const Vec3 xa = random.vector(-1, 1), xb = random.vector(-1, 1);
    const Vec3 va = random.vector(-3, 3), vb = random.vector(-3, 3);
    const double c = random.uniform(0.1, 10);
    const element::ConnectorForce elastic = element::connector_force(xa, xb, va, vb, 0.7, 20.0, 0.0);
    const element::ConnectorForce damped = element::connector_force(xa, xb, va, vb, 0.7, 20.0, c);
    const Vec3 u = (xb - xa) / norm(xb - xa);
    const double rate = dot(vb - va, u);
    expect_vec_near(damped.force_on_a - elastic.force_on_a, c * rate * u, 1e-12, "damping force");
    // The power of the damping forces on both ends, f_a.v_a + f_b.v_b with f_b = -f_a.
    const Vec3 fd = damped.force_on_a - elastic.force_on_a;
    EXPECT_NEAR(damped.damping_power, dot(fd, va) - dot(fd, vb), 1e-12);
    EXPECT_LE(damped.damping_power, 0.0);
  }
}

TEST(ConnectorElement, CoincidentParticlesGiveNoForceAndNoNaN) {
  const element::ConnectorForce f = element::connector_force({1, 2, 3}, {1, 2, 3}, {0, 1, 0}, {1, 0, 0}, 1.0, 80, 5);
  EXPECT_EQ(f.force_on_a, Vec3{});
  EXPECT_EQ(f.damping_power, 0.0);
}

// ---- radial springs -------------------------------------------------------------------------

// Forces on centre, b and c from radial_force, elastic part only.
struct ElementForces {
  Vec3 a, b, c;
};
ElementForces elastic_forces(const Vec3& xa, const Vec3& xb, const Vec3& xc, double rest, double k) {
  const element::RadialForce f = element::radial_force(xa, xb, xc, {}, {}, {}, rest, k, 0.0, 0.0, 0.0);
  return {-(f.force_on_b + f.force_on_c), f.force_on_b, f.force_on_c};
}

void expect_radial_force_is_minus_gradient(const Vec3& xa, const Vec3& xb, const Vec3& xc, double rest, double k,
                                           double tolerance) {
  const ElementForces f = elastic_forces(xa, xb, xc, rest, k);
  const double h = 1e-7;
  const Vec3 ga =
      numerical_gradient([&](const Vec3& x) { return element::radial_energy(x, xb, xc, rest, k, 0.0, 0.0); }, xa, h);
  const Vec3 gb =
      numerical_gradient([&](const Vec3& x) { return element::radial_energy(xa, x, xc, rest, k, 0.0, 0.0); }, xb, h);
  const Vec3 gc =
      numerical_gradient([&](const Vec3& x) { return element::radial_energy(xa, xb, x, rest, k, 0.0, 0.0); }, xc, h);
  const double scale = tolerance * (1 + norm(f.a) + norm(f.b) + norm(f.c));
  expect_vec_near(f.a, -ga, scale, "centre");
  expect_vec_near(f.b, -gb, scale, "b");
  expect_vec_near(f.c, -gc, scale, "c");
}

TEST(RadialElement, ForceIsMinusEnergyGradientForRandomConfigurations) {
  TestRandom random(3);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 xa = random.vector(-1, 1);
    const Vec3 xb = xa + random.vector(-1, 1);
    const Vec3 xc = xa + random.vector(-1, 1);
    const double rest = random.uniform(0, kPi);
    expect_radial_force_is_minus_gradient(xa, xb, xc, rest, random.uniform(1, 1000), 1e-6);
  }
}

TEST(RadialElement, ForceIsMinusEnergyGradientForThePapersRestAngles) {
  TestRandom random(4);
  for (double rest : {kPi / 2, kPi, 0.0}) {
    for (int trial = 0; trial < 100; ++trial) {
      const Vec3 xa = random.vector(-1, 1);
      expect_radial_force_is_minus_gradient(xa, xa + random.vector(-1, 1), xa + random.vector(-1, 1), rest, 1400, 1e-6);
    }
  }
}

// Configurations a small angle `gap` away from straight (theta = pi - gap), bent in a random
// plane: the regime of every opposite spring of a nearly flat sheet.
TEST(RadialElement, NearlyStraightOppositeSpringMatchesGradientAndLinearLimit) {
  const double k = 1400;
  for (double gap : {1e-2, 1e-4, 1e-6}) {
    const Vec3 xa{0.3, -0.2, 0.1};
    const Vec3 xb = xa + Vec3{-1.0, 0.0, 0.0};
    const Vec3 xc = xa + 0.8 * Vec3{std::cos(gap), std::sin(gap), 0.0};  // angle pi - gap
    if (gap >= 1e-4) expect_radial_force_is_minus_gradient(xa, xb, xc, kPi, k, 1e-6);
    // Analytic force on c: magnitude k gap / |e_c|, perpendicular to e_c, towards straightening
    // (away from b's side, i.e. -y here).
    const ElementForces f = elastic_forces(xa, xb, xc, kPi, k);
    EXPECT_NEAR(norm(f.c), k * gap / 0.8, 1e-9 * k) << "gap " << gap;
    EXPECT_LT(f.c.y, 0.0);
    EXPECT_NEAR(dot(f.c, xc - xa), 0.0, 1e-9 * k);
  }
}

TEST(RadialElement, ExactlyStraightOppositeSpringAtRestHasNoForce) {
  const Vec3 xa{0, 0, 0}, xb{-1, 0, 0}, xc{1, 0, 0};
  const element::RadialForce f = element::radial_force(xa, xb, xc, {}, {}, {}, kPi, 1400, 200, 0.0, 0.0);
  EXPECT_EQ(f.force_on_b, Vec3{});
  EXPECT_EQ(f.force_on_c, Vec3{});
  EXPECT_EQ(f.damping_power, 0.0);
  EXPECT_EQ(element::radial_energy(xa, xb, xc, kPi, 1400, 0.0, 0.0), 0.0);
  // Moving along the line (no bending): still nothing.
  const element::RadialForce sliding =
      element::radial_force(xa, xb, xc, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, kPi, 1400, 200, 0.0, 0.0);
  EXPECT_EQ(sliding.force_on_b, Vec3{});
  EXPECT_EQ(sliding.damping_power, 0.0);
}

TEST(RadialElement, ExactlyStraightAdjacentSpringAtRestIsFiniteAndTheMagnitudeLimitIsRight) {
  // A 90-degree spring forced straight: E has a cone point; with no motion to pick a side, the
  // element returns the minimum-norm subgradient, zero.
  const double k = 4;
  const Vec3 xa{0, 0, 0}, xb{-1, 0, 0}, xc{2, 0, 0};
  const element::RadialForce exact = element::radial_force(xa, xb, xc, {}, {}, {}, kPi / 2, k, 1, 0.0, 0.0);
  EXPECT_EQ(exact.force_on_b, Vec3{});
  EXPECT_EQ(exact.force_on_c, Vec3{});
  // Approaching the cone point, the force magnitude tends to k |pi - pi/2| / |e|.
  for (double gap : {1e-3, 1e-6, 1e-9}) {
    const ElementForces f = elastic_forces(xa, xb, 2.0 * Vec3{std::cos(gap), std::sin(gap), 0}, kPi / 2, k);
    EXPECT_NEAR(norm(f.c), k * (kPi / 2 - gap) / 2.0, 1e-6) << "gap " << gap;
    EXPECT_NEAR(norm(f.b), k * (kPi / 2 - gap) / 1.0, 1e-6) << "gap " << gap;
  }
}

TEST(RadialElement, ExactlyFoldedSpringsAtRestAreFinite) {
  // b and c on the same ray from the centre: theta = 0.
  const Vec3 xa{0, 0, 0}, xb{1, 0, 0}, xc{2, 0, 0};
  for (double rest : {kPi, kPi / 2, 0.0}) {
    const element::RadialForce f = element::radial_force(xa, xb, xc, {}, {}, {}, rest, 1400, 200, 0.0, 0.0);
    EXPECT_EQ(f.force_on_b, Vec3{});
    EXPECT_EQ(f.force_on_c, Vec3{});
    EXPECT_EQ(element::radial_angle(xa, xb, xc), 0.0);
  }
  // Nearly folded, opposite spring: magnitude tends to k pi / |e|.
  for (double gap : {1e-3, 1e-7}) {
    const ElementForces f = elastic_forces(xa, xb, Vec3{std::cos(gap), std::sin(gap), 0}, kPi, 10);
    EXPECT_NEAR(norm(f.c), 10 * (kPi - gap), 1e-6) << "gap " << gap;
  }
}

// At an exactly straight or folded configuration that is moving, the force is the limit of the
// force a moment later along the motion: F(x, v) = lim F(x + eps v, v) as eps -> 0+. This is
// what keeps the right-hand side continuous in time for a flat sheet started with any velocity.
TEST(RadialElement, SingularConfigurationsGiveTheOneSidedLimitAlongTheMotion) {
  TestRandom random(12);
  for (int trial = 0; trial < 40; ++trial) {
    const bool straight = trial % 2 == 0;
    const Vec3 xa = random.vector(-1, 1);
    const Vec3 axis = random.vector(-1, 1) / 1.0;
    const Vec3 xb = xa + random.uniform(0.5, 1.5) * axis;
    const Vec3 xc = xa + (straight ? -1.0 : 1.0) * random.uniform(0.5, 1.5) * axis;
    const Vec3 va = random.vector(-1, 1), vb = random.vector(-1, 1), vc = random.vector(-1, 1);
    const double rest = random.uniform(0, kPi);
    const element::RadialForce at = element::radial_force(xa, xb, xc, va, vb, vc, rest, 300, 50, 0.0, 0.0);
    ASSERT_TRUE(is_finite(at.force_on_b) && is_finite(at.force_on_c));
    const double eps = 1e-7;
    const element::RadialForce after =
        element::radial_force(xa + eps * va, xb + eps * vb, xc + eps * vc, va, vb, vc, rest, 300, 50, 0.0, 0.0);
    const double scale = 1e-4 * (1 + norm(after.force_on_b) + norm(after.force_on_c));
    expect_vec_near(at.force_on_b, after.force_on_b, scale, straight ? "straight, b" : "folded, b");
    expect_vec_near(at.force_on_c, after.force_on_c, scale, straight ? "straight, c" : "folded, c");
    EXPECT_NEAR(at.damping_power, after.damping_power, 1e-4 * (1 + std::abs(after.damping_power)));
  }
}

// The element returns the forces on b and c; the centre takes -(f_b + f_c), so there is no net
// force by construction (the assembled sheet's is tested: Forces.InternalForcesSumToZero). What
// the element's formulas decide is the torque: zero about any point, because the forces come from
// an angle, which rotations leave unchanged.
TEST(RadialElement, NoNetTorque) {
  TestRandom random(5);
  for (int trial = 0; trial < 100; ++trial) {
    const Vec3 xa = random.vector(-1, 1), xb = xa + random.vector(-1, 1), xc = xa + random.vector(-1, 1);
    const Vec3 va = random.vector(-1, 1), vb = random.vector(-1, 1), vc = random.vector(-1, 1);
    const element::RadialForce f =
        element::radial_force(xa, xb, xc, va, vb, vc, random.uniform(0, kPi), 300, 20, 0.0, 0.0);
    const Vec3 fa = -(f.force_on_b + f.force_on_c);
    const Vec3 torque = cross(xa, fa) + cross(xb, f.force_on_b) + cross(xc, f.force_on_c);
    const double scale = 1e-11 * (1 + norm(f.force_on_b) + norm(f.force_on_c));
    expect_vec_near(torque, {}, scale, "net torque");
  }
}

TEST(RadialElement, DampingIsMinusCTimesAngleRateAlongTheGradient) {
  TestRandom random(6);
  for (int trial = 0; trial < 100; ++trial) {
    const Vec3 xa = random.vector(-1, 1), xb = xa + random.vector(-1, 1), xc = xa + random.vector(-1, 1);
    const Vec3 va = random.vector(-1, 1), vb = random.vector(-1, 1), vc = random.vector(-1, 1);
    const double c = random.uniform(1, 200);
    // dtheta/dt by central differences along the motion.
    const double dt = 1e-7;
    const double rate = (element::radial_angle(xa + dt * va, xb + dt * vb, xc + dt * vc) -
                         element::radial_angle(xa - dt * va, xb - dt * vb, xc - dt * vc)) /
                        (2 * dt);
    const element::RadialForce damped = element::radial_force(xa, xb, xc, va, vb, vc, 1.0, 0.0, c, 0.0, 0.0);
    EXPECT_NEAR(damped.damping_power, -c * rate * rate, 1e-5 * (1 + c * rate * rate));
    // The damping force is -c rate dtheta/dx: compare on b with the energy-gradient direction.
    const element::RadialGeometry g = element::radial_geometry(xa, xb, xc);
    expect_vec_near(damped.force_on_b, -c * rate * radial_gradient_b(g), 1e-5 * (1 + norm(damped.force_on_b)),
                    "damping on b");
  }
}

// ---- the fade of vanishing arms ----------------------------------------------------------------

// The ramp: 0 at 0, 1 from the fade length on, C2 at both ends (its slope and curvature vanish
// there), its slope d phi / d l the derivative of its value.
TEST(RadialFade, RampIsASmoothStepFromZeroToOne) {
  const double f = 0.3;
  EXPECT_EQ(element::arm_fade(0.0, f).value, 0.0);
  EXPECT_EQ(element::arm_fade(f, f).value, 1.0);
  EXPECT_EQ(element::arm_fade(2 * f, f).value, 1.0);
  EXPECT_EQ(element::arm_fade(2 * f, f).slope, 0.0);
  EXPECT_EQ(element::arm_fade(0.05, 0.0).value, 1.0);  // no fade length: never fades
  EXPECT_NEAR(element::arm_fade(0.5 * f, f).value, 0.5, 1e-15);
  const double h = 1e-6;
  for (double s = 0.01; s < 1.0; s += 0.07) {
    const double l = s * f;
    const double slope = (element::arm_fade(l + h, f).value - element::arm_fade(l - h, f).value) / (2 * h);
    EXPECT_NEAR(element::arm_fade(l, f).slope, slope, 1e-8) << "s = " << s;
  }
  // C2 at both ends: one-sided second differences vanish to O(d) (a C1 smoothstep's would be
  // 6 / f^2 = 67 here).
  const auto value = [&](double l) { return element::arm_fade(l, f).value; };
  const double d = 1e-6;
  EXPECT_NEAR((value(f) - 2 * value(f - d) + value(f - 2 * d)) / (d * d), 0.0, 1e-2);
  EXPECT_NEAR((value(2 * d) - 2 * value(d) + value(0.0)) / (d * d), 0.0, 1e-2);
}

// Radial forces of the faded energy against its negative gradient: arms of random lengths
// inside, across and outside the fade, fade length 0.5 m for both arms.
void expect_faded_force_is_minus_gradient(const Vec3& xa, const Vec3& xb, const Vec3& xc, double rest, double k,
                                          double fade_b, double fade_c) {
  const element::RadialForce f = element::radial_force(xa, xb, xc, {}, {}, {}, rest, k, 0.0, fade_b, fade_c);
  const Vec3 fa = -(f.force_on_b + f.force_on_c);
  const double h = 1e-7;
  const auto energy = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
    return element::radial_energy(a, b, c, rest, k, fade_b, fade_c);
  };
  const Vec3 ga = numerical_gradient([&](const Vec3& x) { return energy(x, xb, xc); }, xa, h);
  const Vec3 gb = numerical_gradient([&](const Vec3& x) { return energy(xa, x, xc); }, xb, h);
  const Vec3 gc = numerical_gradient([&](const Vec3& x) { return energy(xa, xb, x); }, xc, h);
  const double scale = 1e-6 * (1 + norm(fa) + norm(f.force_on_b) + norm(f.force_on_c));
  expect_vec_near(fa, -ga, scale, "centre");
  expect_vec_near(f.force_on_b, -gb, scale, "b");
  expect_vec_near(f.force_on_c, -gc, scale, "c");
}

TEST(RadialFade, FadedForceIsMinusFadedEnergyGradient) {
  TestRandom random(31);
  const double fade = 0.5;
  const auto unit = [](const Vec3& v) { return v / norm(v); };
  int inside = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 xa = random.vector(-1, 1);
    // Arm lengths from 2 % to 160 % of the fade length: inside, across and outside it.
    const double lb = fade * random.uniform(0.02, 1.6);
    const double lc = fade * random.uniform(0.02, 1.6);
    const Vec3 xb = xa + lb * unit(random.vector(-1, 1));
    const Vec3 xc = xa + lc * unit(random.vector(-1, 1));
    if (lb < fade || lc < fade) ++inside;
    expect_faded_force_is_minus_gradient(xa, xb, xc, random.uniform(0, kPi), random.uniform(1, 1000), fade, fade);
  }
  EXPECT_GT(inside, 150);
}

// The fade changes nothing, bit for bit, while both arms are at least their fade length.
TEST(RadialFade, NoFadeOutsideTheFadeLength) {
  TestRandom random(32);
  for (int trial = 0; trial < 100; ++trial) {
    const Vec3 xa = random.vector(-1, 1), xb = xa + random.vector(-1, 1), xc = xa + random.vector(-1, 1);
    const Vec3 va = random.vector(-1, 1), vb = random.vector(-1, 1), vc = random.vector(-1, 1);
    const double rest = random.uniform(0, kPi);
    const double fb = 0.999 * norm(xb - xa);
    const double fc = 0.999 * norm(xc - xa);
    const element::RadialForce plain = element::radial_force(xa, xb, xc, va, vb, vc, rest, 300, 20, 0.0, 0.0);
    const element::RadialForce faded = element::radial_force(xa, xb, xc, va, vb, vc, rest, 300, 20, fb, fc);
    EXPECT_EQ(plain.force_on_b, faded.force_on_b);
    EXPECT_EQ(plain.force_on_c, faded.force_on_c);
    EXPECT_EQ(plain.damping_power, faded.damping_power);
    EXPECT_EQ(element::radial_energy(xa, xb, xc, rest, 300, 0.0, 0.0),
              element::radial_energy(xa, xb, xc, rest, 300, fb, fc));
  }
}

// As an arm vanishes the faded force vanishes with it (the unfaded one grows as 1 / length),
// and the damping fades by the same factor as the energy: -c phi (dtheta/dt) along dtheta/dx.
TEST(RadialFade, ForceAndDampingVanishWithTheArm) {
  const Vec3 xa{0, 0, 0}, xc{1, 0, 0};
  const Vec3 va{}, vb{0, 0, 0.3}, vc{0, 0.2, 0};
  const double fade = 0.5;
  double previous = std::numeric_limits<double>::infinity();
  for (double l : {0.4, 0.1, 0.01, 1e-3, 1e-5}) {
    const Vec3 xb = l * Vec3{0.6, 0.8, 0};
    const element::RadialForce plain = element::radial_force(xa, xb, xc, va, vb, vc, 2.0, 1400, 0.0, 0.0, 0.0);
    const element::RadialForce faded = element::radial_force(xa, xb, xc, va, vb, vc, 2.0, 1400, 0.0, fade, fade);
    EXPECT_GT(norm(plain.force_on_b), 0.9 * 1400 * (2.0 - std::acos(0.6)) / l);
    const double size = norm(faded.force_on_b) + norm(faded.force_on_c);
    EXPECT_LT(size, previous) << "l = " << l;
    previous = size;
    // Damping: the faded spring's damping is phi times the unfaded one's, the same direction.
    const double phi = element::arm_fade(l, fade).value;
    const element::RadialForce damped = element::radial_force(xa, xb, xc, va, vb, vc, 2.0, 0.0, 50, fade, fade);
    const element::RadialForce unfaded_damped = element::radial_force(xa, xb, xc, va, vb, vc, 2.0, 0.0, 50, 0.0, 0.0);
    expect_vec_near(damped.force_on_b, phi * unfaded_damped.force_on_b, 1e-12 * (1 + norm(unfaded_damped.force_on_b)),
                    "faded damping on b");
    EXPECT_NEAR(damped.damping_power, phi * unfaded_damped.damping_power,
                1e-12 * (1 + std::abs(unfaded_damped.damping_power)));
    EXPECT_LE(damped.damping_power, 0.0);
  }
  EXPECT_LT(previous, 1e-4);
}

TEST(RadialElement, XOverSinIsContinuousAcrossTheSeriesSwitch) {
  const double below = std::nextafter(1e-4, 0.0);
  EXPECT_NEAR(element::x_over_sin(below, std::sin(below)), element::x_over_sin(1e-4, std::sin(1e-4)), 1e-15);
  EXPECT_EQ(element::x_over_sin(0.0, 0.0), 1.0);
}

}  // namespace
}  // namespace clothsim
