// Whole runs with events: the energy balance still closes (the released energy is booked as
// plastic and fracture work), torn and plastic runs are bit-identical for any thread count (the
// order of events does not depend on threads), and they stay on the lattice kernel.
#include <gtest/gtest.h>

#include <cstring>

#include "event_fixtures.h"
#include "integrators/explicit_runge_kutta.h"
#include "model/model_edits.h"

namespace clothsim {
namespace {

using namespace clothsim::testing;

// A 16 x 16 sheet of the paper's material held by two corners, falling under gravity: with a
// break strain of 3 % (spread 30 %) it tears at the corners; with a yield strain of 1 % and a
// yield angle of 10 degrees it stretches and creases as it swings.
Simulation changing_sheet(bool tear, int threads) {
  LatticeDef def;
  def.rows = 16;
  def.cols = 16;
  def.spacing = 0.1;
  def.particle_mass = 0.01;
  def.connector = {2000.0, 1.0};
  def.adjacent = {0.05, 0.005};
  def.opposite = {0.2, 0.02};
  const std::vector<Anchor> anchors = {held(0, {-0.75, 0, -0.75}), held(15, {0.75, 0, -0.75})};
  ClothModel model = build_lattice(def, Environment{}, anchors);
  SpringLimits limits;
  if (tear) {
    limits.break_strain = 0.004;
    limits.break_strain_variation = 0.3;
    limits.variation_seed = 3;
  } else {
    limits.yield_strain = 0.001;
    limits.hardening = 0.2;
    limits.opposite_yield_angle = 0.2;
    limits.adjacent_yield_angle = 0.1;
  }
  apply_spring_limits(model, limits);
  ClothState state = make_rest_state(model);
  SimulationSettings settings = event_settings(threads);
  settings.integrator.relative_tolerance = 1e-7;
  settings.integrator.absolute_tolerance = 1e-7;
  return Simulation(std::move(model), std::move(state), settings);
}

TEST(EventRuns, TheEnergyBalanceClosesWithPlasticAndFractureWork) {
  for (bool tear : {true, false}) {
    Simulation simulation = changing_sheet(tear, 1);
    ASSERT_TRUE(simulation.advance_to(1.0)) << simulation.failure()->message;
    const EnergyBalance balance = simulation.energy_balance();
    const ModelChanges changes = simulation.model_changes();
    if (tear) {
      EXPECT_GT(changes.broken_connectors, 0u);
      EXPECT_LT(balance.fracture_work, 0.0);
    } else {
      EXPECT_GT(changes.max_plastic_strain, 0.0);
      EXPECT_GT(changes.max_rest_angle_change, 0.0);
      EXPECT_LT(balance.plastic_work, 0.0);
    }
    // The scale: the gravitational energy the sheet has given up.
    const double scale = std::abs(balance.energy.gravitational);
    EXPECT_LT(std::abs(balance.error()), 1e-4 * scale) << (tear ? "tearing" : "plastic");
    // Without the event work the balance would be off by it.
    EXPECT_GT(std::abs(balance.plastic_work + balance.fracture_work), 10.0 * std::abs(balance.error()));
  }
}

TEST(EventRuns, TornAndPlasticRunsAreBitIdenticalForAnyThreadCount) {
  for (bool tear : {true, false}) {
    Simulation one = changing_sheet(tear, 1);
    ASSERT_TRUE(one.advance_to(0.2));
    ASSERT_GT(one.event_totals().breaks + one.event_totals().yields, 0u);
    for (int threads : {2, 3}) {
      Simulation many = changing_sheet(tear, threads);
      ASSERT_TRUE(many.advance_to(0.2));
      const ClothState& a = one.state();
      const ClothState& b = many.state();
      EXPECT_EQ(std::memcmp(a.position.data(), b.position.data(), a.position.size() * sizeof(Vec3)), 0)
          << threads << " threads, " << (tear ? "tearing" : "plastic");
      EXPECT_EQ(one.model().connector_live, many.model().connector_live);
      EXPECT_EQ(one.model().connector_rest_length, many.model().connector_rest_length);
      EXPECT_EQ(one.model().radial_rest_angle, many.model().radial_rest_angle);
      EXPECT_EQ(a.plastic_work, b.plastic_work);
      EXPECT_EQ(a.fracture_work, b.fracture_work);
    }
  }
}

}  // namespace
}  // namespace clothsim

namespace clothsim {
namespace {

using namespace clothsim::testing;

// A change between steps (here a break through the model's seam) reaches the integrator
// through the model's revision: RKF45 goes on with the step its controller proposed and the
// forces of the changed sheet. The next step (its trials included) equals that of a new
// integrator made for the changed model and started with that step, bit for bit.
TEST(EventRuns, AnIntegratorKeepsItsStepSizeAcrossAModelChange) {
  LatticeDef def;
  def.rows = 6;
  def.cols = 5;
  ClothModel model = build_lattice(def, Environment{}, std::vector<Anchor>{held(2, {0, 0, -2.5})});
  ClothState state = make_rest_state(model);
  IntegratorSettings settings;
  ForceOptions options;
  AdaptiveRungeKutta integrator(model, settings, options, kFehlberg45);
  for (int i = 0; i < 20; ++i) ASSERT_EQ(integrator.step(state, 10.0).status, StepStatus::ok);
  const double proposed = integrator.proposed_step();

  break_connector(model, 3, state.time);
  set_connector_rest_length(model, 10, 1.1);
  ClothState kept = state;
  const std::uint64_t rejected_before = integrator.stats().rejected_steps;
  ASSERT_EQ(integrator.step(kept, 10.0).status, StepStatus::ok);

  settings.time_step = proposed;
  AdaptiveRungeKutta fresh(model, settings, options, kFehlberg45);
  ClothState reference = state;
  ASSERT_EQ(fresh.step(reference, 10.0).status, StepStatus::ok);
  // The same trials (the break makes the first one fail here) and the same accepted step.
  EXPECT_EQ(integrator.stats().rejected_steps - rejected_before, fresh.stats().rejected_steps);
  EXPECT_EQ(integrator.stats().last_step, fresh.stats().last_step);
  EXPECT_EQ(std::memcmp(kept.position.data(), reference.position.data(), kept.position.size() * sizeof(Vec3)), 0);
  EXPECT_EQ(std::memcmp(kept.velocity.data(), reference.velocity.data(), kept.velocity.size() * sizeof(Vec3)), 0);
}

}  // namespace
}  // namespace clothsim
