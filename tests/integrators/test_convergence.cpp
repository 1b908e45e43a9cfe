// The integrator drivers on the cloth ODE itself: a single connector spring with one end
// anchored, against its analytic solution (linear motion along the spring) and the observed order
// of convergence of every method on a nonlinear motion (the spring swinging in a plane).
#include <gtest/gtest.h>

#include <cmath>

#include "integrators/explicit_runge_kutta.h"
#include "integrators/symplectic_euler.h"
#include "single_spring.h"

namespace clothsim {
namespace {

using single_spring::displaced;
using single_spring::kMass;
using single_spring::kRest;
using single_spring::kStiffness;
using single_spring::run;

TEST(SingleSpring, RKF45MatchesTheAnalyticDampedOscillation) {
  const double damping = 1.5;  // N s/m: underdamped
  const ClothModel model = single_spring::model(damping);
  IntegratorSettings settings;
  settings.relative_tolerance = 1e-10;
  settings.absolute_tolerance = 1e-10;
  AdaptiveRungeKutta rkf45(model, settings, ForceOptions{}, kFehlberg45);

  const double amplitude = 0.2;
  const double omega = std::sqrt(kStiffness / kMass);
  const double zeta = damping / (2 * std::sqrt(kStiffness * kMass));
  const double omega_d = omega * std::sqrt(1 - zeta * zeta);
  const auto exact = [&](double t) {
    return amplitude * std::exp(-zeta * omega * t) *
           (std::cos(omega_d * t) + zeta * omega / omega_d * std::sin(omega_d * t));
  };

  ClothState state = displaced(model, amplitude);
  double largest_error = 0.0;
  std::vector<double> upward_crossings;  // times where the extension crosses zero going up
  double previous = amplitude;
  for (int frame = 1; frame <= 600; ++frame) {
    const double t = frame / 200.0;
    state = run(rkf45, state, t);
    const double extension = state.position[1].x - kRest / 2;
    largest_error = std::max(largest_error, std::abs(extension - exact(t)));
    if (previous < 0 && extension >= 0) upward_crossings.push_back(t - extension / (extension - previous) / 200.0);
    previous = extension;
  }
  EXPECT_LT(largest_error, 1e-8);
  // Period and decay, measured from the simulation alone.
  ASSERT_GE(upward_crossings.size(), 3u);
  const double period = (upward_crossings.back() - upward_crossings.front()) / double(upward_crossings.size() - 1);
  EXPECT_NEAR(period, 2 * std::numbers::pi / omega_d, 1e-4);
  // The motion stays on the spring's axis.
  EXPECT_EQ(state.position[1].y, 0.0);
  EXPECT_EQ(state.position[1].z, 0.0);
  // Decay: the energy balance holds, E(t) = E(0) + W_damping.
  const double energy0 = 0.5 * kStiffness * amplitude * amplitude;
  const double extension = state.position[1].x - kRest / 2;
  const double energy = 0.5 * kStiffness * extension * extension + 0.5 * kMass * squared_norm(state.velocity[1]);
  EXPECT_NEAR(energy, energy0 + state.damping_work, 1e-8);
  EXPECT_NEAR(energy / energy0, std::exp(-2 * zeta * omega * 3.0), 0.05);  // envelope, to within the phase ripple
}

// Final state of the swinging spring after 1 s with `steps` fixed steps.
Vec3 swing(Integrator& integrator, const ClothModel& model) {
  ClothState state = displaced(model, 0.3, {0, 0, 2.0});  // stretched and moving sideways: a nonlinear orbit
  return run(integrator, state, 1.0).position[1];
}

template <typename Make>
double observed_order(Make make, int coarse_steps) {
  const ClothModel model = single_spring::model(0.7);
  IntegratorSettings fine_settings;
  fine_settings.time_step = 1.0 / 20000;
  FixedStepRungeKutta reference_integrator(model, fine_settings, ForceOptions{}, kFehlberg45);
  const Vec3 reference = swing(reference_integrator, model);
  double errors[2];
  for (int level = 0; level < 2; ++level) {
    IntegratorSettings settings;
    settings.time_step = 1.0 / (coarse_steps << level);
    auto integrator = make(model, settings);
    errors[level] = norm(swing(*integrator, model) - reference);
  }
  return std::log2(errors[0] / errors[1]);
}

TEST(Convergence, FehlbergFifthOrderRowIsFifthOrder) {
  const double order = observed_order(
      [](const ClothModel& m, const IntegratorSettings& s) {
        return std::make_unique<FixedStepRungeKutta>(m, s, ForceOptions{}, kFehlberg45);
      },
      40);
  EXPECT_NEAR(order, 5.0, 0.35);
}

TEST(Convergence, FehlbergFourthOrderRowIsFourthOrder) {
  const double order = observed_order(
      [](const ClothModel& m, const IntegratorSettings& s) {
        return std::make_unique<FixedStepRungeKutta>(m, s, ForceOptions{}, embedded_as_propagated(kFehlberg45));
      },
      40);
  EXPECT_NEAR(order, 4.0, 0.35);
}

TEST(Convergence, ClassicRk4IsFourthOrder) {
  const double order = observed_order(
      [](const ClothModel& m, const IntegratorSettings& s) {
        return std::make_unique<FixedStepRungeKutta>(m, s, ForceOptions{}, kClassicRk4);
      },
      40);
  EXPECT_NEAR(order, 4.0, 0.35);
}

TEST(Convergence, SymplecticEulerIsFirstOrder) {
  const double order = observed_order(
      [](const ClothModel& m, const IntegratorSettings& s) {
        return std::make_unique<SymplecticEuler>(m, s, ForceOptions{});
      },
      400);
  EXPECT_NEAR(order, 1.0, 0.15);
}

}  // namespace
}  // namespace clothsim
