// A simulation that cannot go on stops with a diagnosis naming time, step and element, and keeps
// its last good state.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "integrators/stable_step.h"
#include "scene/scene.h"
#include "scene/scene_model.h"
#include "scene_simulation.h"
#include "sim/simulation.h"

namespace clothsim {
namespace {

ClothModel hanging_sheet() {
  LatticeDef def;
  def.rows = 5;
  def.cols = 5;
  const Anchor anchor{12, AnchorPath::fixed_at({0, 0, 0})};
  return build_lattice(def, Environment{}, {&anchor, 1});
}

void expect_finite(const ClothState& state) {
  for (std::size_t p = 0; p < state.position.size(); ++p) {
    ASSERT_TRUE(is_finite(state.position[p]) && is_finite(state.velocity[p])) << "particle " << p;
  }
}

TEST(Diagnostics, ExplicitEulerBlowUpStopsWithADiagnosis) {
  ClothModel model = hanging_sheet();
  ClothState state = make_rest_state(model);
  SimulationSettings settings;
  settings.integrator.kind = IntegratorKind::symplectic_euler;
  settings.integrator.time_step = 0.2;  // far beyond the stability limit of c = 200 N m s/rad
  Simulation simulation(std::move(model), std::move(state), settings);
  EXPECT_FALSE(simulation.advance_to(100.0));
  ASSERT_TRUE(simulation.failure().has_value());
  const Diagnosis& diagnosis = *simulation.failure();
  EXPECT_LT(diagnosis.time, 100.0);
  EXPECT_NE(diagnosis.message.find("at t = "), std::string::npos) << diagnosis.message;
  EXPECT_NE(diagnosis.message.find("(step "), std::string::npos) << diagnosis.message;
  EXPECT_FALSE(diagnosis.element.empty());
  EXPECT_NE(diagnosis.message.find(diagnosis.element), std::string::npos);
  // The state is the last good one, and further calls keep failing without touching it.
  expect_finite(simulation.state());
  const double time = simulation.state().time;
  EXPECT_FALSE(simulation.advance_to(200.0));
  EXPECT_EQ(simulation.state().time, time);
}

TEST(Diagnostics, StepFloorStopsRKF45WithTheParticleThatNeedsTheSmallStep) {
  ClothModel model = hanging_sheet();
  ClothState state = make_rest_state(model);
  SimulationSettings settings;
  settings.integrator.relative_tolerance = settings.integrator.absolute_tolerance = 1e-12;
  settings.integrator.min_step = 1e-3;
  Simulation simulation(std::move(model), std::move(state), settings);
  EXPECT_FALSE(simulation.advance_to(1.0));
  ASSERT_TRUE(simulation.failure().has_value());
  EXPECT_NE(simulation.failure()->message.find("step size underflow"), std::string::npos);
  EXPECT_NE(simulation.failure()->message.find("particle"), std::string::npos);
  EXPECT_NE(simulation.failure()->message.find("min_step"), std::string::npos);
  expect_finite(simulation.state());
}

TEST(Diagnostics, OverstretchedConnectorIsReportedAsAnExplosion) {
  ClothModel model = hanging_sheet();
  ClothState state = make_rest_state(model);
  state.position[0] = {5000.0, 0.0, 0.0};  // connector 0 far beyond 1000 x its rest length
  Simulation simulation(std::move(model), std::move(state), SimulationSettings{});
  ASSERT_TRUE(simulation.failure().has_value());
  EXPECT_NE(simulation.failure()->message.find("connector 0 between particle 0 (row 0, col 0)"), std::string::npos)
      << simulation.failure()->message;
  EXPECT_FALSE(simulation.advance_to(0.1));
}

TEST(Diagnostics, NonFiniteInitialStateIsReported) {
  ClothModel model = hanging_sheet();
  ClothState state = make_rest_state(model);
  state.velocity[7].y = std::numeric_limits<double>::quiet_NaN();
  Simulation simulation(std::move(model), std::move(state), SimulationSettings{});
  ASSERT_TRUE(simulation.failure().has_value());
  EXPECT_NE(simulation.failure()->message.find("particle 7 (row 1, col 2)"), std::string::npos);
}

// The paper's 11 x 11 sheet with classical RK4 at `step` s for `duration` s; the simulation after.
Simulation paper_sheet_with_rk4(double step, double duration) {
  SceneSpec spec = scene_from_paper_args("11,11,1,4,1,1400,200,80,5,1", "--paper-args");
  spec.integrator.kind = IntegratorKind::rk4;
  spec.integrator.time_step = step;
  Simulation simulation = testing::one_thread_simulation(spec);
  for (int frame = 1; frame <= static_cast<int>(duration * 30.0); ++frame) {
    if (!simulation.advance_to(frame / 30.0)) break;
  }
  return simulation;
}

// The case that ran to the end and exited 0 with an energy balance off by 7.4e9 J on a sheet whose
// energies are a few kJ (issue 11): it stops, as failed, naming time, step, the fastest particle
// and what to try.
TEST(Diagnostics, BlownUpEnergyBalanceStopsTheRun) {
  const Simulation simulation = paper_sheet_with_rk4(0.01, 2.0);
  ASSERT_TRUE(simulation.failure().has_value()) << "a blown-up run must not complete";
  const Diagnosis& diagnosis = *simulation.failure();
  EXPECT_NE(diagnosis.message.find("blown up"), std::string::npos) << diagnosis.message;
  EXPECT_NE(diagnosis.message.find("integrator.energy_error_limit"), std::string::npos) << diagnosis.message;
  EXPECT_NE(diagnosis.message.find("(step "), std::string::npos) << diagnosis.message;
  EXPECT_NE(diagnosis.message.find("implicit-euler"), std::string::npos) << diagnosis.message;
  EXPECT_NE(diagnosis.message.find(diagnosis.element), std::string::npos);
  EXPECT_LT(diagnosis.time, 2.0);
}

// The advice fits the method that failed: a fixed-step explicit method is pointed at smaller steps
// and the stable methods, implicit Euler (stable, but one Newton step a step) at smaller steps and
// RKF45, and the adaptive methods at their tolerances.
TEST(Diagnostics, BlowUpAdviceFitsTheIntegrator) {
  for (IntegratorKind kind : {IntegratorKind::rk4, IntegratorKind::symplectic_euler}) {
    EXPECT_NE(blow_up_advice(kind).find("implicit-euler (stable for any step)"), std::string::npos);
    EXPECT_NE(blow_up_advice(kind).find("--time-step"), std::string::npos);
  }
  const std::string implicit = blow_up_advice(IntegratorKind::implicit_euler);
  EXPECT_EQ(implicit.find("implicit-euler (stable"), std::string::npos) << "it is running already: " << implicit;
  EXPECT_NE(implicit.find("--time-step"), std::string::npos);
  EXPECT_NE(implicit.find("rkf45"), std::string::npos);
  for (IntegratorKind kind : {IntegratorKind::rkf45, IntegratorKind::imex}) {
    EXPECT_NE(blow_up_advice(kind).find("--rtol"), std::string::npos);
    EXPECT_EQ(blow_up_advice(kind).find("--time-step"), std::string::npos) << "an adaptive method sets its own steps";
  }
}

// The stable-step estimate separates steps that run from steps that blow up: the paper's sheet
// runs 2 s with RK4 at the estimate, energy balance and all, and blows up at 4 times it.
TEST(Diagnostics, StableStepEstimateSeparatesRunningFromBlowingUp) {
  const SceneSpec spec = scene_from_paper_args("11,11,1,4,1,1400,200,80,5,1", "--paper-args");
  const ClothModel model = build_model(spec);
  const double stable = estimate_stable_step(model, IntegratorKind::rk4).step;
  ASSERT_TRUE(stable > 0.0 && stable < 1.0) << stable;
  EXPECT_EQ(estimate_stable_step(model, IntegratorKind::rkf45).step, std::numeric_limits<double>::infinity());
  EXPECT_EQ(estimate_stable_step(model, IntegratorKind::implicit_euler).step, std::numeric_limits<double>::infinity());
  // Symplectic Euler's region is smaller than RK4's.
  EXPECT_LT(estimate_stable_step(model, IntegratorKind::symplectic_euler).step, stable);

  const Simulation at_estimate = paper_sheet_with_rk4(stable, 2.0);
  EXPECT_FALSE(at_estimate.failure().has_value()) << at_estimate.failure()->message;
  const Simulation past_it = paper_sheet_with_rk4(4.0 * stable, 2.0);
  EXPECT_TRUE(past_it.failure().has_value()) << "4 times the estimate, " << 4.0 * stable << " s";
}

}  // namespace
}  // namespace clothsim
