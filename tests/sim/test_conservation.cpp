// Conservation laws of the whole sheet: energy with damping off, the energy balance with damping
// and a moving anchor, linear and angular momentum in free flight, and thread-count independence.
#include <gtest/gtest.h>

#include <cstring>

#include "model/initial_conditions.h"
#include "sim/simulation.h"
#include "simulation_settings.h"

namespace clothsim {
namespace {

using testing::rkf45;

// The paper's material (Figure 5 constants) on a rows x cols lattice.
LatticeDef paper_material(int rows, int cols, bool damped) {
  LatticeDef def;
  def.rows = rows;
  def.cols = cols;
  if (!damped) {
    def.connector.damping = 0.0;
    def.adjacent.damping = 0.0;
    def.opposite.damping = 0.0;
  }
  return def;
}

ClothState perturbed_state(const ClothModel& model, InitialConditions initial) {
  ClothState state = make_rest_state(model);
  apply_initial_conditions(model, initial, state);
  return state;
}

// Largest |E(t) - E(0)| over `frames` frames up to `duration`.
double energy_drift(double tolerance, double duration) {
  InitialConditions initial;
  initial.position_noise = 0.05;
  initial.velocity_noise = 0.5;
  initial.seed = 3;
  ClothModel model = build_lattice(paper_material(6, 6, false), Environment{}, {});
  ClothState state = perturbed_state(model, initial);
  Simulation simulation(std::move(model), std::move(state), rkf45(tolerance));
  const double initial_energy = simulation.energy().total();
  double drift = 0.0;
  for (int frame = 1; frame <= 40; ++frame) {
    EXPECT_TRUE(simulation.advance_to(duration * frame / 40));
    drift = std::max(drift, std::abs(simulation.energy().total() - initial_energy));
  }
  EXPECT_EQ(simulation.state().damping_work, 0.0);
  return drift;
}

TEST(Conservation, EnergyIsConservedWithoutDampingAndTheErrorShrinksWithTheTolerance) {
  const double loose = energy_drift(1e-4, 2.0);
  const double medium = energy_drift(1e-6, 2.0);
  const double tight = energy_drift(1e-8, 2.0);
  EXPECT_LT(medium, loose);
  EXPECT_LT(tight, medium);
  // The sheet falls ~20 m in 2 s: |E_grav| ~ 36 kg * 9.81 m/s^2 * 20 m ~ 7000 J moves through
  // kinetic energy. At 1e-8 the balance holds to better than a part in 1e7 of that.
  EXPECT_LT(tight, 1e-3);
}

TEST(Conservation, EnergyBalanceHoldsWithDampingDragAndAMovingAnchor) {
  LatticeDef def = paper_material(5, 5, true);
  AnchorPath path;
  path.kind = AnchorPathKind::sinusoid;
  // Gentle enough that no radial spring is driven through the cone points of its energy (an
  // adjacent spring folded flat or straightened), where an error-controlled step must shrink to
  // the size of the tolerance (docs/model.md).
  path.amplitude = {0.1, 0.2, 0.0};
  path.frequency = 1.0;
  const Anchor anchor{12, path};  // the centre, at the origin
  ClothModel model = build_lattice(def, Environment{{0, -9.81, 0}, 0.2}, {&anchor, 1});
  ClothState state = make_rest_state(model);
  Simulation simulation(std::move(model), std::move(state), rkf45(1e-8));
  for (int frame = 1; frame <= 20; ++frame) {
    ASSERT_TRUE(simulation.advance_to(frame * 0.1)) << simulation.failure()->message;
    const EnergyBalance balance = simulation.energy_balance();
    const double scale = std::abs(balance.damping_work) + std::abs(balance.drag_work) + std::abs(balance.anchor_work);
    EXPECT_LT(std::abs(balance.error()), 1e-6 * scale) << "t = " << frame * 0.1;
  }
  const EnergyBalance balance = simulation.energy_balance();
  EXPECT_LT(balance.damping_work, 0.0);
  EXPECT_LT(balance.drag_work, 0.0);
  EXPECT_NE(balance.anchor_work, 0.0);
  // The anchor follows its path exactly.
  EXPECT_EQ(simulation.state().position[12], simulation.model().anchors[0].path.position(2.0));
}

Vec3 linear_momentum(const Simulation& s) {
  Vec3 p;
  for (std::size_t i = 0; i < s.model().particle_count(); ++i) p += s.model().particle_mass[i] * s.state().velocity[i];
  return p;
}

Vec3 angular_momentum(const Simulation& s) {
  Vec3 l;
  for (std::size_t i = 0; i < s.model().particle_count(); ++i) {
    l += s.model().particle_mass[i] * cross(s.state().position[i], s.state().velocity[i]);
  }
  return l;
}

TEST(Conservation, FreeFlightConservesLinearAndAngularMomentum) {
  InitialConditions initial;
  initial.velocity = {0.5, 0.2, -0.1};
  initial.angular_velocity = {0.3, 1.0, 0.2};
  initial.position_noise = 0.05;
  initial.velocity_noise = 0.2;
  initial.seed = 11;
  ClothModel model = build_lattice(paper_material(7, 7, true), Environment{{0, 0, 0}, 0.0}, {});
  ClothState state = perturbed_state(model, initial);
  Simulation simulation(std::move(model), std::move(state), rkf45(1e-9));
  const Vec3 p0 = linear_momentum(simulation);
  const Vec3 l0 = angular_momentum(simulation);
  const double kinetic0 = simulation.energy().kinetic;
  for (int frame = 1; frame <= 20; ++frame) {
    ASSERT_TRUE(simulation.advance_to(frame * 0.1));
    // Internal forces cancel pairwise, and RK methods preserve linear invariants exactly: only
    // rounding remains.
    EXPECT_LT(norm(linear_momentum(simulation) - p0), 1e-11 * norm(p0));
    // Angular momentum is a quadratic invariant, kept to the integration tolerance.
    EXPECT_LT(norm(angular_momentum(simulation) - l0), 1e-7 * norm(l0));
  }
  // The damping did work (the perturbation rang down), yet momentum stayed.
  EXPECT_LT(simulation.state().damping_work, 0.0);
  EXPECT_LT(simulation.energy().kinetic, kinetic0);
}

TEST(Determinism, PositionsAreBitIdenticalForAnyThreadCount) {
  InitialConditions initial;
  initial.position_noise = 0.02;
  initial.seed = 5;
  const auto run = [&](int threads) {
    const Anchor anchor{lattice_index(48, 24, 24), AnchorPath::fixed_at({0.5, 0.0, 0.5})};
    ClothModel model = build_lattice(paper_material(48, 48, true), Environment{}, {&anchor, 1});
    ClothState state = perturbed_state(model, initial);
    SimulationSettings settings = rkf45(1e-6);
    settings.threads = threads;
    Simulation simulation(std::move(model), std::move(state), settings);
    EXPECT_EQ(simulation.threads(), threads);
    EXPECT_TRUE(simulation.advance_to(0.02));
    return simulation.state();
  };
  const ClothState one = run(1);
  for (int threads : {2, 3}) {
    const ClothState many = run(threads);
    EXPECT_EQ(std::memcmp(one.position.data(), many.position.data(), one.position.size() * sizeof(Vec3)), 0);
    EXPECT_EQ(std::memcmp(one.velocity.data(), many.velocity.data(), one.velocity.size() * sizeof(Vec3)), 0);
    EXPECT_EQ(one.damping_work, many.damping_work);
  }
}

TEST(Integrators, SymplecticEulerKeepsEnergyBoundedWithoutDamping) {
  InitialConditions initial;
  initial.position_noise = 0.05;
  initial.seed = 9;
  ClothModel model = build_lattice(paper_material(5, 5, false), Environment{{0, 0, 0}, 0.0}, {});
  ClothState state = perturbed_state(model, initial);
  SimulationSettings settings;
  settings.integrator.kind = IntegratorKind::symplectic_euler;
  settings.integrator.time_step = 1e-3;
  Simulation simulation(std::move(model), std::move(state), settings);
  const double e0 = simulation.energy().total();
  double early = 0.0, late = 0.0;
  for (int frame = 1; frame <= 200; ++frame) {
    ASSERT_TRUE(simulation.advance_to(frame * 0.05));
    const double error = std::abs(simulation.energy().total() - e0);
    (frame <= 100 ? early : late) = std::max(frame <= 100 ? early : late, error);
  }
  // No secular drift: the error over the second 5 s is no larger than a small multiple of the first.
  EXPECT_LT(late, 2.0 * early + 1e-12);
  EXPECT_LT(late, 0.05 * e0);
}

}  // namespace
}  // namespace clothsim
