// The Butcher tableaus as data: consistency conditions and the observed order of convergence of
// each weight row on a scalar problem with a known solution.
#include "integrators/tableau.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace clothsim {
namespace {

void expect_consistent(const ButcherTableau& t) {
  for (int i = 0; i < t.stages; ++i) {
    double row = 0.0;
    for (int j = 0; j < i; ++j) row += t.coefficients[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
    EXPECT_NEAR(row, t.nodes[static_cast<std::size_t>(i)], 1e-15) << t.name << " row " << i << " sums to its node";
    for (int j = i; j < kMaxStages; ++j) {
      EXPECT_EQ(t.coefficients[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)], 0.0) << "explicit method";
    }
  }
  double weights = 0.0, embedded = 0.0;
  for (int i = 0; i < t.stages; ++i) {
    weights += t.weights[static_cast<std::size_t>(i)];
    embedded += t.embedded_weights[static_cast<std::size_t>(i)];
  }
  EXPECT_NEAR(weights, 1.0, 1e-15) << t.name;
  if (t.embedded_order > 0) {
    EXPECT_NEAR(embedded, 1.0, 1e-15) << t.name;
  }
}

TEST(Tableau, RowsSumToNodesAndWeightsSumToOne) {
  expect_consistent(kFehlberg45);
  expect_consistent(kClassicRk4);
  expect_consistent(embedded_as_propagated(kFehlberg45));
}

TEST(Tableau, FehlbergMatchesThePapersFigure3) {
  EXPECT_EQ(kFehlberg45.coefficients[3][1], -7200.0 / 2197.0);
  EXPECT_EQ(kFehlberg45.coefficients[5][4], -11.0 / 40.0);
  EXPECT_EQ(kFehlberg45.weights[5], 2.0 / 55.0);           // 5th-order row, propagated
  EXPECT_EQ(kFehlberg45.embedded_weights[4], -1.0 / 5.0);  // 4th-order row, error estimate
}

// Integrates y' = f(t, y) from 0 to `end` in `steps` equal steps with the tableau's weights.
double integrate(const ButcherTableau& t, const std::function<double(double, double)>& f, double y, double end,
                 int steps) {
  const double h = end / steps;
  for (int n = 0; n < steps; ++n) {
    const double time = n * h;
    std::array<double, kMaxStages> k{};
    for (int i = 0; i < t.stages; ++i) {
      double stage = y;
      for (int j = 0; j < i; ++j)
        stage += h * t.coefficients[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] *
                 k[static_cast<std::size_t>(j)];
      k[static_cast<std::size_t>(i)] = f(time + t.nodes[static_cast<std::size_t>(i)] * h, stage);
    }
    for (int i = 0; i < t.stages; ++i) y += h * t.weights[static_cast<std::size_t>(i)] * k[static_cast<std::size_t>(i)];
  }
  return y;
}

// Observed order log2(e(h) / e(h/2)) on y' = y cos t, y(0) = 1, whose solution is exp(sin t):
// non-autonomous and nonlinear in t, so every order condition matters. `steps` must put both
// runs in the asymptotic range: the 4th-order row of RKF45 has a small 4th-order error constant,
// so its error is dominated by 5th-order terms until about 200 steps here (its observed order
// falls from 4.8 at 8 steps to 4.1 at 256).
double observed_order(const ButcherTableau& t, int steps) {
  const auto f = [](double time, double y) { return y * std::cos(time); };
  const double end = 3.0;
  const double exact = std::exp(std::sin(end));
  const double coarse = std::abs(integrate(t, f, 1.0, end, steps) - exact);
  const double fine = std::abs(integrate(t, f, 1.0, end, 2 * steps) - exact);
  return std::log2(coarse / fine);
}

TEST(Tableau, ObservedOrdersMatchTheory) {
  EXPECT_NEAR(observed_order(kFehlberg45, 32), 5.0, 0.2);
  EXPECT_NEAR(observed_order(embedded_as_propagated(kFehlberg45), 256), 4.0, 0.2);
  EXPECT_NEAR(observed_order(kClassicRk4, 64), 4.0, 0.2);
}

}  // namespace
}  // namespace clothsim
