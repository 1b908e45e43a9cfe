// A simulation that cannot go on stops with a diagnosis naming time, step and element, and keeps
// its last good state.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace clothsim
