// Element Jacobians against finite differences of the element forces and energies: the connector
// Jacobian exactly, the radial one as the documented positive semi-definite approximation
// (Gauss-Newton in the plane, the exact curvature out of it where that is non-negative, the exact
// Hessian at a straight pair), and inside the fade of vanishing arms: exact damping, and exact
// stiffness at the rest angle.
#include "forces/element_jacobian.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>

#include "test_support.h"

namespace clothsim {
namespace {

using testing::TestRandom;

constexpr double kPi = std::numbers::pi;
const Vec3 kAxes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

// 9x9 matrices over (centre, b, c) x (x, y, z), index 3 * particle + axis.
using Matrix9 = std::array<std::array<double, 9>, 9>;
using Vector9 = std::array<double, 9>;

Matrix9 radial_stiffness_matrix(const element::RadialJacobian& jacobian) {
  Matrix9 m{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const Mat3 block = jacobian.stiffness_block(i, j);
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) m[3 * i + r][3 * j + c] = block(r, c);
      }
    }
  }
  return m;
}

double quadratic_form(const Matrix9& m, const Vector9& w) {
  double sum = 0.0;
  for (std::size_t i = 0; i < 9; ++i) {
    for (std::size_t j = 0; j < 9; ++j) sum += w[i] * m[i][j] * w[j];
  }
  return sum;
}

// The element's three positions moved by s w.
std::array<Vec3, 3> displaced(const std::array<Vec3, 3>& x, const Vector9& w, double s) {
  std::array<Vec3, 3> out = x;
  for (std::size_t p = 0; p < 3; ++p) out[p] += s * Vec3{w[3 * p], w[3 * p + 1], w[3 * p + 2]};
  return out;
}

double energy(const std::array<Vec3, 3>& x, double rest, double k) {
  return element::radial_energy(x[0], x[1], x[2], rest, k, 0.0, 0.0);
}

// d^2 E / ds^2 along w, central second difference.
double energy_curvature(const std::array<Vec3, 3>& x, const Vector9& w, double rest, double k, double step) {
  return (energy(displaced(x, w, step), rest, k) - 2.0 * energy(x, rest, k) + energy(displaced(x, w, -step), rest, k)) /
         (step * step);
}

// Forces on (centre, b, c) of the elastic part of the radial spring.
std::array<Vec3, 3> radial_forces(const std::array<Vec3, 3>& x, const std::array<Vec3, 3>& v, double rest, double k,
                                  double c) {
  const element::RadialForce f = element::radial_force(x[0], x[1], x[2], v[0], v[1], v[2], rest, k, c, 0.0, 0.0);
  return {-(f.force_on_b + f.force_on_c), f.force_on_b, f.force_on_c};
}

// A random non-singular configuration whose angle is near `angle`.
std::array<Vec3, 3> configuration(TestRandom& random, double angle) {
  const Vec3 centre = random.vector(-1, 1);
  const double lb = random.uniform(0.5, 2.0);
  const double lc = random.uniform(0.5, 2.0);
  // Two unit vectors at the given angle in a random plane.
  Vec3 a = random.vector(-1, 1);
  a = a / norm(a);
  Vec3 t = cross(a, random.vector(-1, 1));
  t = t / norm(t);
  const Vec3 b_direction = a;
  const Vec3 c_direction = std::cos(angle) * a + std::sin(angle) * t;
  return {centre, centre + lb * b_direction, centre + lc * c_direction};
}

// ---- connector springs ----------------------------------------------------------------------

TEST(ConnectorJacobian, StiffnessIsMinusForceDerivativeIncludingGeometricTerm) {
  TestRandom random(11);
  for (int trial = 0; trial < 50; ++trial) {
    const Vec3 xa = random.vector(-1, 1);
    const Vec3 xb = random.vector(-1, 1);
    const double length = norm(xb - xa);
    // Stretched and compressed springs: without the clamp the Jacobian is exact in both.
    const double rest = length * random.uniform(0.5, 1.5);
    const double k = random.uniform(1, 100);
    const element::ConnectorJacobian jacobian = element::connector_jacobian(xa, xb, rest, k, 0.0, false);
    const double h = 1e-6;
    for (int axis = 0; axis < 3; ++axis) {
      const Vec3 e = kAxes[axis];
      const Vec3 plus = element::connector_force(xa, xb + h * e, {}, {}, rest, k, 0.0).force_on_a;
      const Vec3 minus = element::connector_force(xa, xb - h * e, {}, {}, rest, k, 0.0).force_on_a;
      const Vec3 column = (plus - minus) / (2 * h);  // df_a/dx_b, column `axis`
      const Vec3 a_plus = element::connector_force(xa + h * e, xb, {}, {}, rest, k, 0.0).force_on_a;
      const Vec3 a_minus = element::connector_force(xa - h * e, xb, {}, {}, rest, k, 0.0).force_on_a;
      const Vec3 a_column = (a_plus - a_minus) / (2 * h);  // df_a/dx_a = -K
      for (int row = 0; row < 3; ++row) {
        EXPECT_NEAR(jacobian.stiffness(row, axis), column[row], 1e-6 * k) << "trial " << trial;
        EXPECT_NEAR(-jacobian.stiffness(row, axis), a_column[row], 1e-6 * k) << "trial " << trial;
      }
    }
  }
}

TEST(ConnectorJacobian, ClampedStiffnessIsPositiveSemiDefiniteInCompression) {
  TestRandom random(12);
  for (int trial = 0; trial < 50; ++trial) {
    const Vec3 xa = random.vector(-1, 1);
    const Vec3 xb = random.vector(-1, 1);
    const double length = norm(xb - xa);
    const double rest = length * random.uniform(1.1, 3.0);  // compressed
    const element::ConnectorJacobian exact = element::connector_jacobian(xa, xb, rest, 10.0, 0.0, false);
    const element::ConnectorJacobian clamped = element::connector_jacobian(xa, xb, rest, 10.0, 0.0, true);
    const Vec3 u = (xb - xa) / length;
    Vec3 sideways = cross(u, random.vector(-1, 1));
    sideways = sideways / norm(sideways);
    EXPECT_LT(dot(sideways, exact.stiffness * sideways), 0.0) << "the exact geometric term is negative";
    EXPECT_NEAR(dot(sideways, clamped.stiffness * sideways), 0.0, 1e-12);
    EXPECT_NEAR(dot(u, clamped.stiffness * u), 10.0, 1e-12);
    for (int i = 0; i < 20; ++i) {
      const Vec3 w = random.vector(-1, 1);
      EXPECT_GE(dot(w, clamped.stiffness * w), -1e-12);
    }
  }
}

TEST(ConnectorJacobian, DampingIsMinusForceVelocityDerivative) {
  TestRandom random(13);
  for (int trial = 0; trial < 30; ++trial) {
    const Vec3 xa = random.vector(-1, 1), xb = random.vector(-1, 1);
    const Vec3 va = random.vector(-2, 2), vb = random.vector(-2, 2);
    const double c = random.uniform(0.1, 10);
    const element::ConnectorJacobian jacobian = element::connector_jacobian(xa, xb, 0.7, 20.0, c, true);
    const double h = 1e-6;
    for (int axis = 0; axis < 3; ++axis) {
      const Vec3 e = kAxes[axis];
      const Vec3 plus = element::connector_force(xa, xb, va, vb + h * e, 0.7, 20.0, c).force_on_a;
      const Vec3 minus = element::connector_force(xa, xb, va, vb - h * e, 0.7, 20.0, c).force_on_a;
      const Vec3 column = (plus - minus) / (2 * h);  // df_a/dv_b = C
      for (int row = 0; row < 3; ++row) EXPECT_NEAR(jacobian.damping(row, axis), column[row], 1e-7 * c);
    }
  }
}

// ---- radial springs -------------------------------------------------------------------------

TEST(RadialJacobian, GaussNewtonPartIsStiffnessTimesAngleGradientOuterProduct) {
  TestRandom random(21);
  for (int trial = 0; trial < 50; ++trial) {
    const std::array<Vec3, 3> x = configuration(random, random.uniform(0.2, kPi - 0.2));
    const double k = random.uniform(1, 50);
    const element::RadialJacobian jacobian =
        element::radial_jacobian(x[0], x[1], x[2], {}, {}, {}, 1.0, k, 0.0, 0.0, 0.0);
    EXPECT_EQ(jacobian.in_plane_stiffness, k);
    for (std::size_t p = 0; p < 3; ++p) {
      const Vec3 numerical = testing::numerical_gradient(
          [&](const Vec3& moved) {
            std::array<Vec3, 3> y = x;
            y[p] = moved;
            return element::radial_angle(y[0], y[1], y[2]);
          },
          x[p], 1e-6);
      for (int axis = 0; axis < 3; ++axis) {
        EXPECT_NEAR(jacobian.gradient[p][axis], numerical[axis], 1e-7) << "particle " << p << " trial " << trial;
      }
    }
  }
}

TEST(RadialJacobian, StiffnessIsPositiveSemiDefinite) {
  TestRandom random(22);
  for (int trial = 0; trial < 200; ++trial) {
    const std::array<Vec3, 3> x = configuration(random, random.uniform(0.01, kPi - 0.01));
    const double rest = random.uniform(0.0, kPi);
    const element::RadialJacobian jacobian =
        element::radial_jacobian(x[0], x[1], x[2], {}, {}, {}, rest, 10.0, 0.0, 0.0, 0.0);
    const Matrix9 m = radial_stiffness_matrix(jacobian);
    for (std::size_t i = 0; i < 9; ++i) {
      for (std::size_t j = 0; j < 9; ++j) EXPECT_NEAR(m[i][j], m[j][i], 1e-9) << "symmetric";
    }
    for (int sample = 0; sample < 20; ++sample) {
      Vector9 w;
      for (double& value : w) value = random.uniform(-1, 1);
      EXPECT_GE(quadratic_form(m, w), -1e-9) << "trial " << trial;
    }
  }
}

// Out of the plane, the approximation is the exact energy curvature along equal tilts of both
// connectors (the bending of a nearly straight pair), and the exact curvature clamped at zero
// along opposite tilts.
TEST(RadialJacobian, OutOfPlaneCurvatureIsExactWhereNonNegative) {
  TestRandom random(23);
  for (int trial = 0; trial < 40; ++trial) {
    const bool opposite = trial % 2 == 0;
    const double rest = opposite ? kPi : kPi / 2;
    const double angle = opposite ? random.uniform(kPi / 2 + 0.1, kPi - 0.05) : random.uniform(0.3, kPi - 0.3);
    const std::array<Vec3, 3> x = configuration(random, angle);
    const double k = 7.0;
    const element::RadialJacobian jacobian =
        element::radial_jacobian(x[0], x[1], x[2], {}, {}, {}, rest, k, 0.0, 0.0, 0.0);
    const Matrix9 m = radial_stiffness_matrix(jacobian);
    const Vec3 eb = x[1] - x[0], ec = x[2] - x[0];
    Vec3 n = cross(eb, ec);
    n = n / norm(n);
    // Tilt both connectors by the same (equal) or opposite angle: move b by |e_b| n, c by +-|e_c| n.
    for (const double sign : {1.0, -1.0}) {
      Vector9 w{};
      for (int axis = 0; axis < 3; ++axis) {
        w[static_cast<std::size_t>(3 + axis)] = norm(eb) * n[axis];
        w[static_cast<std::size_t>(6 + axis)] = sign * norm(ec) * n[axis];
      }
      const double exact = energy_curvature(x, w, rest, k, 1e-4);
      const double approximate = quadratic_form(m, w);
      EXPECT_NEAR(approximate, std::max(0.0, exact), 1e-5 * (1 + std::abs(exact)))
          << (sign > 0 ? "equal" : "opposite") << " tilts, angle " << angle << ", rest " << rest;
    }
  }
}

// At an exactly straight pair at its rest angle pi the energy is smooth and the approximation is
// its whole Hessian: the derivative of the elastic forces.
TEST(RadialJacobian, StraightPairIsTheExactHessian) {
  TestRandom random(24);
  for (int trial = 0; trial < 10; ++trial) {
    const Vec3 centre = random.vector(-1, 1);
    Vec3 u = random.vector(-1, 1);
    u = u / norm(u);
    const std::array<Vec3, 3> x = {centre, centre + random.uniform(0.5, 2) * u, centre - random.uniform(0.5, 2) * u};
    const double k = 3.0;
    const element::RadialJacobian jacobian =
        element::radial_jacobian(x[0], x[1], x[2], {}, {}, {}, kPi, k, 0.0, 0.0, 0.0);
    const Matrix9 m = radial_stiffness_matrix(jacobian);
    const std::array<Vec3, 3> still{};
    const double h = 1e-6;
    for (std::size_t j = 0; j < 9; ++j) {
      Vector9 w{};
      w[j] = 1.0;
      const std::array<Vec3, 3> plus = radial_forces(displaced(x, w, h), still, kPi, k, 0.0);
      const std::array<Vec3, 3> minus = radial_forces(displaced(x, w, -h), still, kPi, k, 0.0);
      for (std::size_t i = 0; i < 9; ++i) {
        const int axis = static_cast<int>(i % 3);
        const double derivative = (plus[i / 3][axis] - minus[i / 3][axis]) / (2 * h);
        EXPECT_NEAR(m[i][j], -derivative, 1e-5 * k) << "entry (" << i << ", " << j << ")";
      }
    }
  }
}

TEST(RadialJacobian, DampingIsMinusForceVelocityDerivative) {
  TestRandom random(25);
  for (int trial = 0; trial < 30; ++trial) {
    const std::array<Vec3, 3> x = configuration(random, random.uniform(0.2, kPi - 0.2));
    const std::array<Vec3, 3> v = {random.vector(-1, 1), random.vector(-1, 1), random.vector(-1, 1)};
    const double c = random.uniform(0.5, 5);
    const element::RadialJacobian jacobian =
        element::radial_jacobian(x[0], x[1], x[2], v[0], v[1], v[2], 1.0, 0.0, c, 0.0, 0.0);
    const double h = 1e-6;
    for (int j = 0; j < 3; ++j) {
      for (int axis = 0; axis < 3; ++axis) {
        std::array<Vec3, 3> vp = v, vm = v;
        vp[static_cast<std::size_t>(j)] += h * kAxes[axis];
        vm[static_cast<std::size_t>(j)] -= h * kAxes[axis];
        const std::array<Vec3, 3> fp = radial_forces(x, vp, 1.0, 0.0, c);
        const std::array<Vec3, 3> fm = radial_forces(x, vm, 1.0, 0.0, c);
        for (int i = 0; i < 3; ++i) {
          const Mat3 block = jacobian.damping_block(i, j);
          const Vec3 column = (fp[static_cast<std::size_t>(i)] - fm[static_cast<std::size_t>(i)]) / (2 * h);
          for (int row = 0; row < 3; ++row) EXPECT_NEAR(block(row, axis), -column[row], 1e-7 * c);
        }
      }
    }
  }
}

// ---- the fade of vanishing arms ----------------------------------------------------------------

// Forces on (centre, b, c) with both arms' fade lengths.
std::array<Vec3, 3> faded_forces(const std::array<Vec3, 3>& x, const std::array<Vec3, 3>& v, double rest, double k,
                                 double c, double fade_b, double fade_c) {
  const element::RadialForce f = element::radial_force(x[0], x[1], x[2], v[0], v[1], v[2], rest, k, c, fade_b, fade_c);
  return {-(f.force_on_b + f.force_on_c), f.force_on_b, f.force_on_c};
}

// Fade lengths that put both arms of x inside the fade, at 40 % to 90 % of it.
std::array<double, 2> fade_lengths_inside(TestRandom& random, const std::array<Vec3, 3>& x) {
  return {norm(x[1] - x[0]) / random.uniform(0.4, 0.9), norm(x[2] - x[0]) / random.uniform(0.4, 0.9)};
}

// Inside the fade the damping Jacobian phi c g g^T is exact.
TEST(RadialJacobian, FadedDampingIsMinusForceVelocityDerivative) {
  TestRandom random(26);
  for (int trial = 0; trial < 30; ++trial) {
    const std::array<Vec3, 3> x = configuration(random, random.uniform(0.2, kPi - 0.2));
    const std::array<Vec3, 3> v = {random.vector(-1, 1), random.vector(-1, 1), random.vector(-1, 1)};
    const std::array<double, 2> fade = fade_lengths_inside(random, x);
    const double c = random.uniform(0.5, 5);
    const element::RadialJacobian jacobian =
        element::radial_jacobian(x[0], x[1], x[2], v[0], v[1], v[2], 1.0, 0.0, c, fade[0], fade[1]);
    EXPECT_LT(jacobian.damping, c);
    const double h = 1e-6;
    for (int j = 0; j < 3; ++j) {
      for (int axis = 0; axis < 3; ++axis) {
        std::array<Vec3, 3> vp = v, vm = v;
        vp[static_cast<std::size_t>(j)] += h * kAxes[axis];
        vm[static_cast<std::size_t>(j)] -= h * kAxes[axis];
        const std::array<Vec3, 3> fp = faded_forces(x, vp, 1.0, 0.0, c, fade[0], fade[1]);
        const std::array<Vec3, 3> fm = faded_forces(x, vm, 1.0, 0.0, c, fade[0], fade[1]);
        for (int i = 0; i < 3; ++i) {
          const Mat3 block = jacobian.damping_block(i, j);
          const Vec3 column = (fp[static_cast<std::size_t>(i)] - fm[static_cast<std::size_t>(i)]) / (2 * h);
          for (int row = 0; row < 3; ++row) EXPECT_NEAR(block(row, axis), -column[row], 1e-7 * c);
        }
      }
    }
  }
}

// At the rest angle the faded stiffness phi k g g^T is the exact -df/dx of the faded force
// (element_jacobian.h: the fade's own terms carry E or dE, both zero there).
TEST(RadialJacobian, FadedStiffnessIsExactAtTheRestAngle) {
  TestRandom random(27);
  for (int trial = 0; trial < 30; ++trial) {
    const double rest = random.uniform(0.3, kPi - 0.3);
    const std::array<Vec3, 3> x = configuration(random, rest);
    const double angle = element::radial_angle(x[0], x[1], x[2]);
    const std::array<double, 2> fade = fade_lengths_inside(random, x);
    const double k = random.uniform(1, 50);
    const element::RadialJacobian jacobian =
        element::radial_jacobian(x[0], x[1], x[2], {}, {}, {}, angle, k, 0.0, fade[0], fade[1]);
    const Matrix9 m = radial_stiffness_matrix(jacobian);
    const std::array<Vec3, 3> still{};
    const double h = 1e-6;
    for (std::size_t j = 0; j < 9; ++j) {
      Vector9 w{};
      w[j] = 1.0;
      const std::array<Vec3, 3> plus = faded_forces(displaced(x, w, h), still, angle, k, 0.0, fade[0], fade[1]);
      const std::array<Vec3, 3> minus = faded_forces(displaced(x, w, -h), still, angle, k, 0.0, fade[0], fade[1]);
      for (std::size_t i = 0; i < 9; ++i) {
        const double derivative =
            (plus[i / 3][static_cast<int>(i % 3)] - minus[i / 3][static_cast<int>(i % 3)]) / (2 * h);
        EXPECT_NEAR(m[i][j], -derivative, 1e-5 * k) << "entry (" << i << ", " << j << "), trial " << trial;
      }
    }
  }
}

// Away from the rest angle the faded stiffness is phi times the unfaded approximation (the
// documented one), so it stays symmetric positive semi-definite and vanishes with the arm.
TEST(RadialJacobian, FadedStiffnessIsTheFadeTimesTheUnfadedApproximation) {
  TestRandom random(28);
  for (int trial = 0; trial < 50; ++trial) {
    const std::array<Vec3, 3> x = configuration(random, random.uniform(0.05, kPi - 0.05));
    const std::array<double, 2> fade = fade_lengths_inside(random, x);
    const double rest = random.uniform(0.0, kPi);
    const double phi =
        element::arm_fade(norm(x[1] - x[0]), fade[0]).value * element::arm_fade(norm(x[2] - x[0]), fade[1]).value;
    ASSERT_LT(phi, 1.0);
    const Matrix9 faded = radial_stiffness_matrix(
        element::radial_jacobian(x[0], x[1], x[2], {}, {}, {}, rest, 10.0, 0.0, fade[0], fade[1]));
    const Matrix9 plain =
        radial_stiffness_matrix(element::radial_jacobian(x[0], x[1], x[2], {}, {}, {}, rest, 10.0, 0.0, 0.0, 0.0));
    for (std::size_t i = 0; i < 9; ++i) {
      for (std::size_t j = 0; j < 9; ++j)
        EXPECT_NEAR(faded[i][j], phi * plain[i][j], 1e-12 * (1 + std::abs(plain[i][j])));
    }
  }
}

}  // namespace
}  // namespace clothsim
