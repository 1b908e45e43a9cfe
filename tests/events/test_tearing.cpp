// Tearing (DESIGN.md section 3): a connector breaks when its strain against its original length
// passes its threshold s_e = break_strain (1 + variation u_e), taking its radial springs along;
// the pieces separate; mass is conserved; the released energy is booked as fracture work.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <numeric>

#include "event_fixtures.h"
#include "events/spring_events.h"
#include "forces/forces.h"
#include "model/model_edits.h"

namespace clothsim {
namespace {

using namespace clothsim::testing;

// A 1 x 5 strip, the left end held, the right end pulled at 1 m/s for `duration` seconds: the
// strip's mean strain reaches duration / 4.
Simulation pulled_strip(double break_strain, double duration) {
  ClothModel model = strip(5, {held(0, {-2, 0, 0}), pulled(4, {2, 0, 0}, {1, 0, 0})});
  SpringLimits limits;
  limits.break_strain = break_strain;
  apply_spring_limits(model, limits);
  ClothState state = make_rest_state(model);
  Simulation simulation(std::move(model), std::move(state), event_settings());
  EXPECT_TRUE(simulation.advance_to(duration));
  return simulation;
}

TEST(Tearing, AStripPulledPastItsBreakStrainTearsAndBelowItDoesNot) {
  // Pulled to a mean strain of 15 %: past a 10 % break strain, short of a 20 % one.
  const Simulation torn = pulled_strip(0.10, 0.6);
  const Simulation whole = pulled_strip(0.20, 0.6);
  EXPECT_GE(torn.model_changes().broken_connectors, 1u);
  EXPECT_EQ(whole.model_changes().broken_connectors, 0u);
  EXPECT_EQ(whole.event_totals().breaks, 0u);
  // Every intact connector of the whole strip is below its threshold, every broken one of the
  // torn strip was past it when it broke (it cannot be shorter now: its end went on moving away).
  for (std::size_t e = 0; e < whole.model().connector_count(); ++e) {
    const auto [a, b] = whole.model().connector_particles[e];
    EXPECT_LE(distance(whole.state(), a, b) - 1.0, 0.20);
  }
}

TEST(Tearing, ABrokenConnectorTakesItsRadialSpringsAlongAndExertsNoForce) {
  ClothModel model = strip(4);
  // Connector 1 joins particles 1 and 2; the opposite springs at particles 1 and 2 use it.
  ASSERT_TRUE(break_connector(model, 1));
  EXPECT_FALSE(break_connector(model, 1));  // once only
  EXPECT_EQ(model.connector_live[1], 0);
  EXPECT_EQ(model.broken_connector_count, 1u);
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    const auto [c1, c2] = model.radial_connectors[r];
    EXPECT_EQ(model.radial_live[r], (c1 == 1 || c2 == 1) ? 0 : 1) << "radial " << r;
  }
  // Particles 2 and 3 pulled apart from 0 and 1: no force across the broken connector.
  std::vector<Vec3> x = model.particle_rest_position;
  x[2].x += 5.0;
  x[3].x += 5.0;
  const std::vector<Vec3> v(x.size());
  for (ForceKernel kernel : {ForceKernel::general, ForceKernel::lattice}) {
    ForceBuffers buffers;
    buffers.kernel = kernel;
    buffers.resize(model);
    std::vector<Vec3> force(x.size());
    evaluate_forces(model, x, v, kAllForceTerms, 1, buffers, force);
    for (const Vec3& f : force) EXPECT_EQ(f, Vec3{});
  }
  EXPECT_EQ(connector_energy(model, x), 0.0);
}

TEST(Tearing, ThePiecesSeparateAndMassIsConserved) {
  Simulation simulation = pulled_strip(0.10, 0.6);
  const double mass_before =
      std::accumulate(simulation.model().particle_mass.begin(), simulation.model().particle_mass.end(), 0.0);
  ASSERT_GE(simulation.model_changes().broken_connectors, 1u);
  // Keep pulling: the piece on the pulled side follows the anchor, the other stays behind.
  std::size_t broken = 0;
  for (std::size_t e = 0; e < simulation.model().connector_count(); ++e) {
    if (simulation.model().connector_live[e] == 0) broken = e;
  }
  const auto [a, b] = simulation.model().connector_particles[broken];
  const double gap_before = distance(simulation.state(), a, b);
  ASSERT_TRUE(simulation.advance_to(2.0));
  EXPECT_GT(distance(simulation.state(), a, b), gap_before + 0.5);
  const double mass_after =
      std::accumulate(simulation.model().particle_mass.begin(), simulation.model().particle_mass.end(), 0.0);
  EXPECT_EQ(mass_after, mass_before);
  EXPECT_EQ(simulation.model().particle_count(), 5u);
  EXPECT_EQ(count_pieces(simulation.model()), 1u + simulation.model_changes().broken_connectors);
}

// A piece torn off may fall as far as it likes: a broken connector is no measure of an explosion
// (the check of a connector stretched past 1000 times its rest length skips it).
TEST(Tearing, APieceThatFallsAwayIsNotAnExplosion) {
  ClothModel model = strip(3, {held(0, {-1, 0, 0})});
  model.environment.gravity = {0.0, -9.81, 0.0};
  ClothState state = make_rest_state(model);
  SimulationSettings settings = event_settings();
  settings.explosion_stretch = 10.0;
  Simulation simulation(std::move(model), std::move(state), settings);
  const std::array<std::uint32_t, 1> cut = {0};
  ASSERT_EQ(simulation.cut_connectors(cut), 1u);
  ASSERT_TRUE(simulation.advance_to(3.0)) << simulation.failure()->message;  // falls 44 m
  EXPECT_GT(distance(simulation.state(), 0, 1), 40.0);
}

TEST(Tearing, ThresholdsVaryBySeedWithinTheirSpread) {
  ClothModel model = strip(200);
  SpringLimits limits;
  limits.break_strain = 0.2;
  limits.break_strain_variation = 0.25;
  limits.variation_seed = 7;
  apply_spring_limits(model, limits);
  const auto [low, high] =
      std::minmax_element(model.connector_break_strain.begin(), model.connector_break_strain.end());
  EXPECT_GE(*low, 0.2 * 0.75);
  EXPECT_LE(*high, 0.2 * 1.25);
  EXPECT_LT(*low, 0.2 * 0.8);  // 199 draws spread over the whole range
  EXPECT_GT(*high, 0.2 * 1.2);
  // The same seed gives the same thresholds; another seed other ones.
  ClothModel again = strip(200);
  apply_spring_limits(again, limits);
  EXPECT_EQ(again.connector_break_strain, model.connector_break_strain);
  limits.variation_seed = 8;
  apply_spring_limits(again, limits);
  EXPECT_NE(again.connector_break_strain, model.connector_break_strain);
}

// Breaks found after one step go in together, in index order, whatever the thread count; the
// energy they release is the elastic energy of the springs removed.
TEST(Tearing, BreaksReleaseTheirElasticEnergyAsFractureWork) {
  ClothModel model = strip(6);
  SpringLimits limits;
  limits.break_strain = 0.1;
  apply_spring_limits(model, limits);
  ClothState state = make_rest_state(model);
  for (std::size_t p = 0; p < 6; ++p) state.position[p].x *= 1.2;  // every connector at 20 % strain
  state.position[3].y = 0.3;                                       // and a kink
  EnergyReport before = compute_energy(model, state);
  SpringEvents events;
  const SpringEventCounts counts = events.apply(model, state, 1);
  EXPECT_EQ(counts.breaks, 5u);
  EXPECT_EQ(model.broken_connector_count, 5u);
  EnergyReport after = compute_energy(model, state);
  EXPECT_EQ(after.connector + after.radial_opposite, 0.0);
  EXPECT_NEAR(state.fracture_work, after.total() - before.total(), 1e-12 * before.total());
  EXPECT_LT(state.fracture_work, 0.0);
}

}  // namespace
}  // namespace clothsim
