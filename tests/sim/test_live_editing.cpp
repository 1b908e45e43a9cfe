// Live editing between steps (Simulation::set_*, runtime anchors): an edit takes effect from the
// next step on, as if the run had been started afresh from that state with the edited model; the
// state survives an integrator switch; and the energy balance stays exact across every edit,
// with parameter edits booked as edit work and anchor velocity jumps as anchor work.
#include <gtest/gtest.h>

#include <cmath>

#include "forces/element.h"
#include "model/initial_conditions.h"
#include "sim/simulation.h"
#include "simulation_settings.h"

namespace clothsim {
namespace {

using testing::rk4;
using testing::rkf45;

constexpr std::uint32_t kCentre = 12;  // of a 5 x 5 lattice
constexpr std::uint32_t kCorner = 0;

ClothModel hanging_sheet(const LatticeDef& def, const Environment& environment = Environment{}) {
  const Anchor anchor{kCentre, AnchorPath::fixed_at({0, 0, 0})};
  return build_lattice(def, environment, {&anchor, 1});
}

LatticeDef five_by_five() {
  LatticeDef def;
  def.rows = 5;
  def.cols = 5;
  return def;
}

// |balance error| relative to the energy that moved through the sheet's books.
double relative_balance_error(const EnergyBalance& balance) {
  const double scale = std::abs(balance.damping_work) + std::abs(balance.drag_work) + std::abs(balance.anchor_work) +
                       std::abs(balance.edit_work) + std::abs(balance.energy.kinetic);
  return std::abs(balance.error()) / scale;
}

TEST(LiveEditing, StiffnessEditActsFromTheNextStepAsIfTheRunHadRestartedThere) {
  Simulation edited(hanging_sheet(five_by_five()), make_rest_state(hanging_sheet(five_by_five())), rk4(2e-4));
  ASSERT_TRUE(edited.advance_to(0.2)) << edited.failure()->message;
  const ClothState at_edit = edited.state();
  const double connector_energy_before = edited.energy().connector;
  ASSERT_GT(connector_energy_before, 0.0);

  edited.set_spring_parameters(SpringFamily::connector, {160.0, 5.0});
  // The force law changed at once: the stretch energy of the same positions doubled (exactly:
  // every term is scaled by 2), and the state did not move.
  EXPECT_EQ(edited.energy().connector, 2.0 * connector_energy_before);
  EXPECT_EQ(edited.state().position, at_edit.position);
  ASSERT_TRUE(edited.advance_to(0.4));

  // The oracle: a fresh run from the state at the edit, with the edited material.
  LatticeDef stiffer = five_by_five();
  stiffer.connector = {160.0, 5.0};
  Simulation restarted(hanging_sheet(stiffer), at_edit, rk4(2e-4));
  ASSERT_TRUE(restarted.advance_to(0.4));
  EXPECT_EQ(edited.state().position, restarted.state().position);
  EXPECT_EQ(edited.state().velocity, restarted.state().velocity);

  // And the edit mattered: without it the run ends elsewhere.
  Simulation unedited(hanging_sheet(five_by_five()), at_edit, rk4(2e-4));
  ASSERT_TRUE(unedited.advance_to(0.4));
  EXPECT_NE(edited.state().position, unedited.state().position);
}

TEST(LiveEditing, EveryParameterEditMatchesARestartWithTheEditedModel) {
  Simulation edited(hanging_sheet(five_by_five()), make_rest_state(hanging_sheet(five_by_five())), rk4(2e-4));
  ASSERT_TRUE(edited.advance_to(0.3));
  const ClothState at_edit = edited.state();
  const Environment environment{{0.5, -3.0, 0.0}, 0.4};
  edited.set_spring_parameters(SpringFamily::adjacent, {2.0, 0.5});
  edited.set_spring_parameters(SpringFamily::opposite, {700.0, 100.0});
  edited.set_environment(environment);
  edited.set_particle_mass(0.5);
  ASSERT_TRUE(edited.advance_to(0.5));

  LatticeDef def = five_by_five();
  def.adjacent = {2.0, 0.5};
  def.opposite = {700.0, 100.0};
  def.particle_mass = 0.5;
  Simulation restarted(hanging_sheet(def, environment), at_edit, rk4(2e-4));
  ASSERT_TRUE(restarted.advance_to(0.5));
  EXPECT_EQ(edited.state().position, restarted.state().position);
  EXPECT_EQ(edited.state().velocity, restarted.state().velocity);
  EXPECT_EQ(edited.model().particle_inverse_mass, restarted.model().particle_inverse_mass);
}

TEST(LiveEditing, SwitchingIntegratorKeepsTheStateAndGoesOnWithTheNewMethod) {
  Simulation simulation(hanging_sheet(five_by_five()), make_rest_state(hanging_sheet(five_by_five())), rkf45(1e-6));
  ASSERT_TRUE(simulation.advance_to(0.3));
  const ClothState at_switch = simulation.state();
  const std::uint64_t rkf45_steps = simulation.integrator_stats().accepted_steps;

  IntegratorSettings fixed;
  fixed.kind = IntegratorKind::rk4;
  fixed.time_step = 2e-4;  // within RK4's stable step on this material (4e-4 s; integrators/stable_step.h)
  simulation.set_integrator(fixed);
  EXPECT_EQ(simulation.settings().integrator.kind, IntegratorKind::rk4);
  EXPECT_EQ(simulation.state().position, at_switch.position);
  EXPECT_EQ(simulation.state().velocity, at_switch.velocity);
  EXPECT_EQ(simulation.state().time, at_switch.time);
  ASSERT_TRUE(simulation.advance_to(0.5));

  Simulation restarted(hanging_sheet(five_by_five()), at_switch, rk4(2e-4));
  ASSERT_TRUE(restarted.advance_to(0.5));
  EXPECT_EQ(simulation.state().position, restarted.state().position);
  EXPECT_EQ(simulation.state().velocity, restarted.state().velocity);
  // Statistics count across the switch: the rkf45 steps and 1,000 rk4 steps of 0.2 ms.
  EXPECT_EQ(simulation.integrator_stats().accepted_steps, rkf45_steps + 1000);
  EXPECT_EQ(simulation.integrator_stats().last_step, restarted.integrator_stats().last_step);
}

// The energy each edit adds, written here from the physics rather than from the simulation's
// energy function: a stiffness change of the adjacent radial springs adds 1/2 (k_new - k_old)
// (theta - theta0)^2 per spring, a gravity change -m (g_new - g_old).x per particle, a mass
// change (m_new - m_old) (|v|^2 / 2 - g.x) per particle.
double adjacent_stiffness_jump(const ClothModel& model, const ClothState& state, double k_new) {
  double jump = 0.0;
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    if (model.radial_kind[r] != RadialKind::adjacent) continue;
    const auto [a, b, c] = model.radial_particles[r];
    const double bend =
        element::radial_angle(state.position[a], state.position[b], state.position[c]) - model.radial_rest_angle[r];
    jump += 0.5 * (k_new - model.radial_stiffness[r]) * bend * bend;
  }
  return jump;
}

double gravity_jump(const ClothModel& model, const ClothState& state, const Vec3& g_new) {
  double jump = 0.0;
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    jump -= model.particle_mass[p] * dot(g_new - model.environment.gravity, state.position[p]);
  }
  return jump;
}

double mass_jump(const ClothModel& model, const ClothState& state, double m_new) {
  double jump = 0.0;
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    const double specific = 0.5 * squared_norm(state.velocity[p]) - dot(model.environment.gravity, state.position[p]);
    jump += (m_new - model.particle_mass[p]) * specific;
  }
  return jump;
}

// The sheet's energy summed here from the textbook formulas (kinetic, -m g.x, 1/2 k (l - L)^2 per
// connector, 1/2 k (theta - theta0)^2 per radial spring), not by the simulation's energy function.
double hand_energy(const ClothModel& model, const ClothState& state) {
  double energy = 0.0;
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    energy += model.particle_mass[p] *
              (0.5 * squared_norm(state.velocity[p]) - dot(model.environment.gravity, state.position[p]));
  }
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    const auto [a, b] = model.connector_particles[e];
    const double stretch = norm(state.position[b] - state.position[a]) - model.connector_rest_length[e];
    energy += 0.5 * model.connector_stiffness[e] * stretch * stretch;
  }
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    const auto [a, b, c] = model.radial_particles[r];
    const double bend =
        element::radial_angle(state.position[a], state.position[b], state.position[c]) - model.radial_rest_angle[r];
    energy += 0.5 * model.radial_stiffness[r] * bend * bend;
  }
  return energy;
}

TEST(LiveEditing, EnergyBalanceStaysExactAcrossParameterEdits) {
  Simulation simulation(hanging_sheet(five_by_five(), Environment{{0, -9.81, 0}, 0.1}),
                        make_rest_state(hanging_sheet(five_by_five())), rkf45(1e-9));
  ASSERT_TRUE(simulation.advance_to(0.5));
  const double before = simulation.energy().total();
  double expected = adjacent_stiffness_jump(simulation.model(), simulation.state(), 40.0);
  simulation.set_spring_parameters(SpringFamily::adjacent, {40.0, 1.0});  // the sheet is bent: energy changes
  expected += gravity_jump(simulation.model(), simulation.state(), {0, -4.0, 0});
  simulation.set_environment(Environment{{0, -4.0, 0}, 0.3});
  expected += mass_jump(simulation.model(), simulation.state(), 2.0);
  simulation.set_particle_mass(2.0);
  const EnergyBalance at_edit = simulation.energy_balance();
  // The edit work is the energy the edits added, so the balance holds across them.
  EXPECT_NEAR(at_edit.edit_work, expected, 1e-9 * (1.0 + std::abs(expected)));
  EXPECT_NEAR(simulation.energy().total() - before, expected, 1e-9 * (1.0 + std::abs(expected)));
  EXPECT_GT(std::abs(at_edit.edit_work), 1.0);
  EXPECT_LT(relative_balance_error(at_edit), 1e-7);
  for (int frame = 1; frame <= 10; ++frame) {
    ASSERT_TRUE(simulation.advance_to(0.5 + 0.05 * frame)) << simulation.failure()->message;
    EXPECT_LT(relative_balance_error(simulation.energy_balance()), 1e-7) << "frame " << frame;
  }
}

TEST(RuntimeAnchors, PinningAMovingParticleHoldsItAndBooksItsKineticEnergyAsAnchorWork) {
  Simulation simulation(hanging_sheet(five_by_five()), make_rest_state(hanging_sheet(five_by_five())), rkf45(1e-9));
  ASSERT_TRUE(simulation.advance_to(0.4));
  const Vec3 where = simulation.state().position[kCorner];
  const Vec3 velocity = simulation.state().velocity[kCorner];
  ASSERT_GT(norm(velocity), 0.01);
  const double anchor_work_before = simulation.state().anchor_work;

  simulation.pin_particle(kCorner);
  EXPECT_TRUE(simulation.model().is_anchored(kCorner));
  EXPECT_EQ(simulation.model().particle_inverse_mass[kCorner], 0.0);
  EXPECT_EQ(simulation.state().velocity[kCorner], Vec3{});
  EXPECT_DOUBLE_EQ(simulation.state().anchor_work - anchor_work_before,
                   -0.5 * simulation.model().particle_mass[kCorner] * squared_norm(velocity));
  ASSERT_TRUE(simulation.advance_to(0.8));
  EXPECT_EQ(simulation.state().position[kCorner], where);
  EXPECT_LT(relative_balance_error(simulation.energy_balance()), 1e-7);

  // Unpinning frees it (mass restored) and gravity takes it again.
  EXPECT_TRUE(simulation.release_particle(kCorner));
  EXPECT_FALSE(simulation.release_particle(kCorner));
  EXPECT_EQ(simulation.model().particle_inverse_mass[kCorner], 1.0 / simulation.model().particle_mass[kCorner]);
  ASSERT_TRUE(simulation.advance_to(1.0));
  EXPECT_NE(simulation.state().position[kCorner], where);
}

TEST(RuntimeAnchors, DrivenParticleArrivesAtItsTargetAndTheBalanceSeesTheWork) {
  Simulation simulation(hanging_sheet(five_by_five(), Environment{{0, -9.81, 0}, 0.2}),
                        make_rest_state(hanging_sheet(five_by_five())), rkf45(1e-9));
  ASSERT_TRUE(simulation.advance_to(0.25));
  const Vec3 start = simulation.state().position[kCorner];
  const Vec3 target{-3.0, 1.5, -2.5};
  const double arrival = 0.25 + 0.537;  // not on a frame time: the arrival is its own event
  simulation.drive_particle(kCorner, target, arrival);
  const Vec3 drive_velocity = (target - start) / 0.537;
  EXPECT_TRUE(simulation.model().is_anchored(kCorner));
  EXPECT_EQ(simulation.state().velocity[kCorner], drive_velocity);

  for (int frame = 1; frame <= 60; ++frame) {
    const double time = 0.25 + frame / 60.0;
    ASSERT_TRUE(simulation.advance_to(time)) << simulation.failure()->message;
    const Vec3 expected = time < arrival ? start + (time - 0.25) * drive_velocity : target;
    EXPECT_LT(norm(simulation.state().position[kCorner] - expected), 1e-12) << "t = " << time;
    EXPECT_EQ(simulation.state().velocity[kCorner], time < arrival ? drive_velocity : Vec3{}) << "t = " << time;
    EXPECT_LT(relative_balance_error(simulation.energy_balance()), 1e-7) << "t = " << time;
  }
  // The hand lifted the corner 1.5 m against gravity and the springs: it did positive work.
  EXPECT_GT(simulation.state().anchor_work, 0.0);
}

TEST(RuntimeAnchors, ReAimingEveryFrameFollowsAMovingTarget) {
  Simulation simulation(hanging_sheet(five_by_five()), make_rest_state(hanging_sheet(five_by_five())), rk4(2e-4));
  const auto cursor = [](double t) { return Vec3{-2.0 + std::sin(3.0 * t), 0.5 * t, -2.0}; };
  for (int frame = 1; frame <= 30; ++frame) {
    const double time = frame / 30.0;
    simulation.drive_particle(kCorner, cursor(time), time);
    ASSERT_TRUE(simulation.advance_to(time));
    EXPECT_LT(norm(simulation.state().position[kCorner] - cursor(time)), 1e-12) << "frame " << frame;
  }
}

TEST(RuntimeAnchors, ReleasingADrivenParticleKeepsItsVelocityAndRestoresItsMass) {
  Simulation simulation(hanging_sheet(five_by_five()), make_rest_state(hanging_sheet(five_by_five())), rkf45(1e-9));
  simulation.drive_particle(kCorner, {-2.0, 2.0, -2.0}, 1.0);
  ASSERT_TRUE(simulation.advance_to(0.5));
  const Vec3 velocity = simulation.state().velocity[kCorner];
  const double anchor_work = simulation.state().anchor_work;
  EXPECT_TRUE(simulation.release_particle(kCorner));
  EXPECT_FALSE(simulation.model().is_anchored(kCorner));
  EXPECT_EQ(simulation.model().particle_inverse_mass[kCorner], 1.0 / simulation.model().particle_mass[kCorner]);
  EXPECT_EQ(simulation.state().velocity[kCorner], velocity);
  EXPECT_EQ(simulation.state().anchor_work, anchor_work);  // no impulse: nothing jumped
  // The released particle flies on: it is not stopped at the old arrival time.
  ASSERT_TRUE(simulation.advance_to(1.2));
  EXPECT_NE(simulation.state().velocity[kCorner], Vec3{});
  EXPECT_LT(relative_balance_error(simulation.energy_balance()), 1e-7);
}

TEST(RuntimeAnchors, PlacingAnAnchoredParticleBooksTheJumpAsEditWork) {
  Simulation simulation(hanging_sheet(five_by_five()), make_rest_state(hanging_sheet(five_by_five())), rkf45(1e-9));
  ASSERT_TRUE(simulation.advance_to(0.3));
  simulation.pin_particle(kCorner);
  const double before = hand_energy(simulation.model(), simulation.state());
  const double edit_work = simulation.energy_balance().edit_work;
  simulation.place_particle(kCorner, {-2.5, 0.5, -2.5});
  EXPECT_EQ(simulation.state().position[kCorner], (Vec3{-2.5, 0.5, -2.5}));
  EXPECT_EQ(simulation.state().time, 0.3);
  // The jump of the energy, summed independently, is what the balance books as edit work.
  const double jump = hand_energy(simulation.model(), simulation.state()) - before;
  EXPECT_GT(std::abs(jump), 1.0) << "the placed corner stretches its springs and moves in height";
  EXPECT_NEAR(simulation.energy_balance().edit_work - edit_work, jump, 1e-9 * (1.0 + std::abs(jump)));
  ASSERT_TRUE(simulation.advance_to(0.6));
  EXPECT_EQ(simulation.state().position[kCorner], (Vec3{-2.5, 0.5, -2.5}));
  EXPECT_LT(relative_balance_error(simulation.energy_balance()), 1e-7);
}

// energy() hands out the energies the last blow-up check computed (Simulation::checked_energy_):
// after each edit, and after restoring a checkpoint, it must give the edited sheet's own, the
// energies computed afresh from the model and the state, bit for bit.
TEST(LiveEditing, EnergiesAreTheEditedSheetsAfterEveryEdit) {
  Simulation simulation(hanging_sheet(five_by_five()), make_rest_state(hanging_sheet(five_by_five())), rk4(2e-4));
  double time = 0.0;
  const auto expect_current = [&](const char* edit) {
    const EnergyReport fresh = compute_energy(simulation.model(), simulation.state(), simulation.settings().terms, 1);
    const EnergyReport given = simulation.energy();
    EXPECT_EQ(given.total(), fresh.total()) << "after " << edit;
    EXPECT_EQ(given.connector, fresh.connector) << "after " << edit;
    EXPECT_EQ(given.gravitational, fresh.gravitational) << "after " << edit;
    time += 0.05;
    ASSERT_TRUE(simulation.advance_to(time)) << simulation.failure()->message;
  };
  time = 0.1;
  ASSERT_TRUE(simulation.advance_to(time));
  expect_current("a step");
  simulation.set_spring_parameters(SpringFamily::connector, {160.0, 5.0});
  expect_current("set_spring_parameters");
  Environment heavier = simulation.model().environment;
  heavier.gravity = 2.0 * heavier.gravity;
  simulation.set_environment(heavier);
  expect_current("set_environment");
  simulation.set_particle_mass(2.0 * simulation.model().particle_mass[0]);
  expect_current("set_particle_mass");
  const std::uint32_t cut[] = {0};
  simulation.cut_connectors(cut);
  expect_current("cut_connectors");
  simulation.pin_particle(kCorner);
  simulation.place_particle(kCorner, {-2.5, 0.5, -2.5});
  expect_current("place_particle");
  ASSERT_TRUE(simulation.release_particle(kCorner));
  expect_current("release_particle");
}

}  // namespace
}  // namespace clothsim
