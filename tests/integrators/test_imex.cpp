// The IMEX pair (integrators/imex.h) on problems with known answers: the tableau's order
// conditions, the observed orders of its solution and of its embedded estimate on a damped
// nonlinear swing (the damping implicit, the spring explicit), and a stiff damped oscillator at
// steps far past any explicit method's stability limit against its analytic solution.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "integrators/explicit_runge_kutta.h"
#include "integrators/imex.h"
#include "single_spring.h"

namespace clothsim {
namespace {

using single_spring::displaced;
using single_spring::kMass;
using single_spring::kRest;
using single_spring::kStiffness;
using single_spring::run;

TEST(ImexTableau, SatisfiesTheOrderConditionsOfBothParts) {
  const AdditiveTableau& t = kArk324L2SA;
  const auto n = static_cast<std::size_t>(t.stages);
  for (const auto* a : {&t.explicit_coefficients, &t.implicit_coefficients}) {
    for (std::size_t i = 0; i < n; ++i) {
      double row = 0.0;
      for (std::size_t j = 0; j < n; ++j) row += (*a)[i][j];
      EXPECT_NEAR(row, t.nodes[i], 1e-12) << "row " << i;  // c_i = sum_j a_ij
    }
    // Third order: b.1 = 1, b.c = 1/2, b.c^2 = 1/3, b.A.c = 1/6 (and the coupling b.A^E.c and
    // b.A^I.c, each 1/6, since both parts share b and c).
    double b1 = 0, bc = 0, bc2 = 0, bac = 0;
    for (std::size_t i = 0; i < n; ++i) {
      b1 += t.weights[i];
      bc += t.weights[i] * t.nodes[i];
      bc2 += t.weights[i] * t.nodes[i] * t.nodes[i];
      for (std::size_t j = 0; j < n; ++j) bac += t.weights[i] * (*a)[i][j] * t.nodes[j];
    }
    EXPECT_NEAR(b1, 1.0, 1e-12);
    EXPECT_NEAR(bc, 0.5, 1e-12);
    EXPECT_NEAR(bc2, 1.0 / 3.0, 1e-12);
    EXPECT_NEAR(bac, 1.0 / 6.0, 1e-12);
  }
  // The embedded row: second order.
  double b1 = 0, bc = 0;
  for (std::size_t i = 0; i < n; ++i) {
    b1 += t.embedded_weights[i];
    bc += t.embedded_weights[i] * t.nodes[i];
  }
  EXPECT_NEAR(b1, 1.0, 1e-12);
  EXPECT_NEAR(bc, 0.5, 1e-12);
  // ESDIRK and stiffly accurate: a^I_11 = 0, one gamma on the diagonal, last row = b.
  EXPECT_EQ(t.implicit_coefficients[0][0], 0.0);
  for (std::size_t i = 1; i < n; ++i) EXPECT_EQ(t.implicit_coefficients[i][i], t.gamma());
  for (std::size_t j = 0; j < n; ++j) EXPECT_EQ(t.implicit_coefficients[n - 1][j], t.weights[j]);
}

// The swinging spring of test_convergence.cpp, damped so that the implicit part matters
// (c/m = 20 per second against the spring's 9 rad/s): its position after 1 s.
constexpr double kSwingDamping = 20.0;  // N s/m

Vec3 swing(Integrator& integrator, const ClothModel& model) {
  ClothState state = displaced(model, 0.3);
  state.velocity[1] = {0, 0, 2.0};  // stretched and moving sideways: a nonlinear orbit
  return run(integrator, state, 1.0).position[1];
}

double observed_order(const AdditiveTableau& tableau, int coarse_steps) {
  const ClothModel model = single_spring::model(kSwingDamping);
  IntegratorSettings fine_settings;
  fine_settings.time_step = 1.0 / 20000;
  FixedStepRungeKutta reference_integrator(model, fine_settings, ForceOptions{}, kFehlberg45);
  const Vec3 reference = swing(reference_integrator, model);
  double errors[2];
  for (int level = 0; level < 2; ++level) {
    IntegratorSettings settings;
    settings.time_step = 1.0 / (coarse_steps << level);
    AdditiveRungeKutta integrator(model, settings, ForceOptions{}, tableau, /*fixed_step=*/true);
    errors[level] = norm(swing(integrator, model) - reference);
  }
  return std::log2(errors[0] / errors[1]);
}

TEST(ImexConvergence, SolutionIsThirdOrder) { EXPECT_NEAR(observed_order(kArk324L2SA, 100), 3.0, 0.3); }

TEST(ImexConvergence, EmbeddedSolutionIsSecondOrder) {
  EXPECT_NEAR(observed_order(embedded_as_propagated(kArk324L2SA), 100), 2.0, 0.3);
}

// m x'' = -k x - c x' with c/m = 1e4 per second (overdamped): the fast mode decays at nearly
// c/m, the slow one at about k/c. An explicit method's step is bounded by its stability on the
// fast mode, about 2.8 / 1e4 s for RKF45 and RK4 (integrators/stable_step.cpp); imex takes steps
// set by the slow motion's accuracy alone.
TEST(ImexStiffOscillator, FollowsTheAnalyticSolutionAtStepsFarPastTheExplicitLimit) {
  const double damping = 1e4;  // N s/m, c/m = 1e4 / s
  const ClothModel model = single_spring::model(damping);
  IntegratorSettings settings;
  settings.kind = IntegratorKind::imex;
  settings.max_step = 10.0;
  AdditiveRungeKutta imex(model, settings, ForceOptions{});
  const double amplitude = 0.2;
  const double root = std::sqrt(damping * damping - 4 * kStiffness * kMass);
  const double fast = (-damping - root) / (2 * kMass);  // 1/s
  const double slow = (-damping + root) / (2 * kMass);
  // x(0) = amplitude, v(0) = 0.
  const auto exact = [&](double t) {
    return amplitude * (fast * std::exp(slow * t) - slow * std::exp(fast * t)) / (fast - slow);
  };
  ClothState state = displaced(model, amplitude);
  double largest_error = 0.0;
  const double end = 100.0;  // s: the slow mode decays to e^-0.8
  for (int frame = 1; frame <= 100; ++frame) {
    state = run(imex, state, frame * end / 100);
    largest_error = std::max(largest_error, std::abs(state.position[1].x - kRest / 2 - exact(state.time)));
  }
  const double explicit_limit = 2.8 / damping;  // s
  const IntegratorStats& stats = imex.stats();
  // 100 times past the explicit limit on average, after the first transient steps.
  EXPECT_LT(static_cast<double>(stats.accepted_steps), end / (100 * explicit_limit)) << stats.accepted_steps;
  EXPECT_GT(stats.largest_step, 100 * explicit_limit);
  // Within the tolerance (rtol = atol = 1e-6 per step) over the whole run.
  EXPECT_LT(largest_error, 1e-5) << largest_error;
}

TEST(ImexStiffOscillator, RefusesAStepBelowTheFloorWithADiagnosis) {
  const ClothModel model = single_spring::model(10.0);
  IntegratorSettings settings;
  settings.kind = IntegratorKind::imex;
  settings.relative_tolerance = 1e-14;
  settings.absolute_tolerance = 1e-300;
  settings.min_step = 1e-3;
  AdditiveRungeKutta imex(model, settings, ForceOptions{});
  ClothState state = displaced(model, 0.2);
  const StepOutcome outcome = imex.step(state, 1.0);
  EXPECT_EQ(outcome.status, StepStatus::step_underflow);
  EXPECT_EQ(outcome.particle, 1u);
  EXPECT_GT(imex.stats().rejected_steps, 0u);
}

}  // namespace
}  // namespace clothsim
