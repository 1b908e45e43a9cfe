// The viewer's window-free core (apps/clothsim/viewer/session.h): what a script or the mouse does
// to the simulation, without a display. A scripted drag ends at its target, a scripted run is
// reproducible, "set" changes the running simulation and survives a reset, the hand restores
// what it found, the work budget bounds one frame's simulation, a scripted cut breaks the
// connectors it crosses, and edited spring limits survive a reset.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "model/sheet_mesh.h"
#include "session_fixtures.h"
#include "viewer/session.h"

namespace clothsim::viewer {
namespace {

using fixtures::kFrameTime;
using fixtures::small_scene;

// Plays `script` for frames 0..last as the window does: frame k > 0 first advances one frame
// while playing, then fires frame k's events.
void play(Session& session, ScriptPlayer& player, std::uint64_t last) {
  for (std::uint64_t frame = 0; frame <= last; ++frame) {
    if (frame > 0 && session.playing()) {
      ASSERT_GT(session.advance(kFrameTime), 0.0);
    }
    const ScriptPlayer::FrameRequests requests = player.fire(frame, session);
    if (requests.quit) return;
  }
}

TEST(Session, ScriptedDragEndsAtItsTargetAndReleaseFreesTheParticle) {
  Session session(small_scene());
  const Script script = parse_script(R"({"events": [
      {"at": 0.25, "drag": {"row": 0, "col": 0, "to": [-3, 1.5, -2.5], "duration": 0.5}},
      {"at": 1.0, "release": {"row": 0, "col": 0}}]})",
                                     "drag.json");
  check_script(script, session.scene());
  ScriptPlayer player(script, kFrameTime);
  play(session, player, 50);  // t = 50/60 s: arrived at 0.75 s, still held
  const std::uint32_t corner = session.particle(0, 0);
  EXPECT_TRUE(session.is_held(corner));
  EXPECT_LT(norm(session.simulation().state().position[corner] - Vec3{-3, 1.5, -2.5}), 1e-12);
  EXPECT_EQ(session.simulation().state().velocity[corner], Vec3{});

  for (std::uint64_t frame = 51; frame <= 60; ++frame) {
    session.advance(kFrameTime);
    player.fire(frame, session);
  }
  EXPECT_FALSE(session.is_held(corner));
  EXPECT_FALSE(session.simulation().model().is_anchored(corner));
  EXPECT_EQ(session.simulation().model().particle_inverse_mass[corner], 1.0);
  session.advance(0.1);
  EXPECT_GT(norm(session.simulation().state().position[corner] - Vec3{-3, 1.5, -2.5}), 1e-3);  // it falls
}

// A drag (a driven anchor added and moved), a pin, live edits of a spring family and of the
// integrator, and a release.
constexpr const char* kDragPinSetRelease = R"({"events": [
    {"at": 0.1, "drag": {"row": 4, "col": 2, "to": [0, 2, 3], "duration": 0.3}},
    {"at": 0.2, "pin": {"row": 0, "col": 0}},
    {"at": 0.3, "set": {"springs.adjacent.stiffness": 40, "integrator.method": "rk4", "integrator.time_step": 0.0002}},
    {"at": 0.5, "release": {"row": 4, "col": 2}}]})";

TEST(Session, ScriptedRunsAreReproducible) {
  const Script script = parse_script(kDragPinSetRelease, "run.json");
  const auto run = [&script] {
    Session session(small_scene());
    ScriptPlayer player(script, kFrameTime);
    play(session, player, 45);
    return session.simulation().state();
  };
  const ClothState first = run();
  const ClothState second = run();
  EXPECT_NEAR(first.time, 45 * kFrameTime, 1e-12);
  EXPECT_EQ(first.position, second.position);
  EXPECT_EQ(first.velocity, second.velocity);
}

#if defined(CLOTHSIM_HAVE_VULKAN)
// The viewer on the Vulkan backend (`clothsim view --backend vulkan`): the same script (a drag
// that adds a driven anchor and moves it, a pin, live edits of a spring family and of the
// integrator, a release) plays on the device as on the CPU. float64, so the two differ by the
// error control's slack only.
TEST(Session, AScriptPlaysOnTheVulkanBackendAsOnTheCpu) {
  const Script script = parse_script(kDragPinSetRelease, "run.json");
  const auto run = [&script](const BackendSettings& backend) {
    SceneSpec scene = small_scene();
    scene.backend = backend;
    Session session(scene);
    ScriptPlayer player(script, kFrameTime);
    play(session, player, 45);
    return session.simulation().state();
  };
  const ClothState cpu = run(BackendSettings{Backend::cpu, 0, PrecisionRequest::float64});
  const ClothState device = run(BackendSettings{Backend::vulkan, 0, PrecisionRequest::float64});
  EXPECT_EQ(device.time, cpu.time);
  for (std::size_t p = 0; p < cpu.position.size(); ++p) {
    EXPECT_LT(norm(device.position[p] - cpu.position[p]), 1e-6) << "particle " << p;
    EXPECT_LT(norm(device.velocity[p] - cpu.velocity[p]), 1e-4) << "particle " << p;
  }
}
#endif

TEST(Session, SetChangesTheRunningSimulationAndSurvivesAReset) {
  Session session(small_scene());
  session.advance(0.2);
  session.set_parameters({{"springs.connector.stiffness", "160"},
                          {"environment.gravity", "0,-4,0"},
                          {"lattice.particle_mass", "2"},
                          {"integrator.method", "rk4"}},
                         "test");
  const Simulation& simulation = session.simulation();
  EXPECT_EQ(simulation.model().connector_stiffness.front(), 160.0);
  EXPECT_EQ(simulation.model().environment.gravity, (Vec3{0, -4, 0}));
  EXPECT_EQ(simulation.model().particle_mass.front(), 2.0);
  EXPECT_EQ(simulation.settings().integrator.kind, IntegratorKind::rk4);
  EXPECT_EQ(session.time(), 0.2);  // the state went on where it was
  EXPECT_NE(simulation.energy_balance().edit_work, 0.0);
  EXPECT_EQ(session.scene().lattice.connector.stiffness, 160.0);

  session.reset();
  EXPECT_EQ(session.time(), 0.0);
  EXPECT_EQ(session.simulation().model().connector_stiffness.front(), 160.0);
  EXPECT_EQ(session.simulation().settings().integrator.kind, IntegratorKind::rk4);
  EXPECT_EQ(session.simulation().energy_balance().edit_work, 0.0);
}

TEST(Session, RefusedSetChangesNothing) {
  Session session(small_scene());
  // A key that is not live, and a bad value after a good one: neither is applied.
  EXPECT_THROW(session.set_parameters({{"lattice.rows", "7"}}, "test"), InputError);
  EXPECT_THROW(
      session.set_parameters({{"springs.connector.stiffness", "10"}, {"springs.connector.damping", "-1"}}, "test"),
      InputError);
  // min_step above max_step breaks a cross-field rule only together.
  EXPECT_THROW(session.set_parameters({{"integrator.min_step", "0.5"}, {"integrator.max_step", "0.01"}}, "test"),
               InputError);
  EXPECT_EQ(session.simulation().model().connector_stiffness.front(), 80.0);
  EXPECT_EQ(session.scene().lattice.connector.stiffness, 80.0);
  EXPECT_EQ(session.scene().integrator.min_step, SceneSpec{}.integrator.min_step);
}

TEST(Session, ReleasingAParticleThatWasPinnedPinsItWhereItWasLetGo) {
  Session session(small_scene());
  const std::uint32_t centre = session.particle(2, 2);  // the scene's anchor
  ASSERT_TRUE(session.is_pinned(centre));
  session.drag(centre, {0.0, 1.0, 0.0}, 0.25);
  EXPECT_FALSE(session.is_pinned(centre));
  session.advance(0.5);
  session.release(centre);
  EXPECT_TRUE(session.is_pinned(centre));
  EXPECT_LT(norm(session.simulation().state().position[centre] - Vec3{0, 1, 0}), 1e-12);
  session.advance(0.2);
  EXPECT_LT(norm(session.simulation().state().position[centre] - Vec3{0, 1, 0}), 1e-12);

  session.unpin(centre);
  EXPECT_FALSE(session.simulation().model().is_anchored(centre));
  session.pin(centre);
  EXPECT_TRUE(session.is_pinned(centre));
}

TEST(Session, DragWhilePausedPlacesTheParticleAtOnce) {
  Session session(small_scene());
  session.advance(0.1);
  session.set_playing(false);
  const std::uint32_t corner = session.particle(4, 4);
  session.drag(corner, {3.0, 0.5, 3.0}, 0.5);
  EXPECT_EQ(session.simulation().state().position[corner], (Vec3{3.0, 0.5, 3.0}));
  EXPECT_EQ(session.time(), 0.1);
  EXPECT_TRUE(session.is_held(corner));
  const EnergyBalance balance = session.simulation().energy_balance();
  EXPECT_LT(std::abs(balance.error()), 1e-6 * (std::abs(balance.edit_work) + std::abs(balance.anchor_work)));
}

TEST(Session, WorkBudgetStopsAFrameEarly) {
  Session session(small_scene());
  // A budget that is spent by the first piece: one piece of simulated time, not the whole second.
  const double advanced = session.advance(1.0, 1e-12, 0.01);
  EXPECT_DOUBLE_EQ(advanced, 0.01);
  EXPECT_DOUBLE_EQ(session.time(), 0.01);
  // No budget: the whole duration.
  EXPECT_DOUBLE_EQ(session.advance(0.05), 0.05);
}

TEST(Session, EnergyHistoryKeepsItsWindow) {
  Session session(small_scene());
  for (int frame = 0; frame <= 30; ++frame) {
    if (frame > 0) session.advance(0.1);
    session.record_energy(0.95);
    session.record_energy(0.95);  // the same time twice is one sample
  }
  const auto& history = session.energy_history();
  ASSERT_EQ(history.size(), 10u);  // t = 2.1 .. 3.0
  EXPECT_NEAR(history.front().time, 2.1, 1e-9);
  EXPECT_NEAR(history.back().time, 3.0, 1e-9);
  const EnergyReport energy = session.simulation().energy();
  EXPECT_EQ(history.back().kinetic, energy.kinetic);
  EXPECT_DOUBLE_EQ(history.back().potential + history.back().kinetic, energy.total());
}

TEST(Session, PauseAndPlayEventsAndQuit) {
  Session session(small_scene());
  // Pause at frame 1, a screenshot while paused, play again at 0.05 s (frame 3), quit at frame 4:
  // each switch finds the session in the other state, so a switch that did nothing would show.
  ScriptPlayer player(parse_script(R"({"events": [{"frame": 4, "quit": true}, {"at": 0.05, "play": true},
                                                  {"frame": 2, "screenshot": "a.png"}, {"frame": 1, "pause": true}]})",
                                   "p.json"),
                      kFrameTime);
  EXPECT_EQ(player.last_event_frame(), 4u);
  EXPECT_TRUE(player.fire(0, session).screenshots.empty());
  EXPECT_TRUE(session.playing());
  player.fire(1, session);
  EXPECT_FALSE(session.playing());
  const ScriptPlayer::FrameRequests second = player.fire(2, session);
  EXPECT_FALSE(session.playing());
  ASSERT_EQ(second.screenshots.size(), 1u);
  EXPECT_EQ(second.screenshots[0], "a.png");
  EXPECT_FALSE(second.quit);
  player.fire(3, session);
  EXPECT_TRUE(session.playing());  // 0.05 s is frame 3
  EXPECT_TRUE(player.fire(4, session).quit);
}

TEST(Session, ScriptedCutBreaksTheConnectorsItCrosses) {
  Session session(small_scene());  // 5 x 5, the centre (2, 2) anchored
  const Script script =
      parse_script(R"({"events": [{"at": 0.1, "cut": {"from": [2.5, -1], "to": [2.5, 9]}}]})", "cut.json");
  check_script(script, session.scene());
  ScriptPlayer player(script, kFrameTime);
  play(session, player, 30);
  const ClothModel& model = session.simulation().model();
  // Exactly the 5 connectors from row 2 south to row 3 are broken, with their radial springs.
  EXPECT_EQ(model.broken_connector_count, 5u);
  for (std::uint32_t e = 0; e < model.connector_count(); ++e) {
    const auto [a, b] = model.connector_particles[e];
    const bool crossed = a / 5 == 2 && b == a + 5;
    EXPECT_EQ(model.connector_live[e] == 0, crossed) << "connector " << e;
  }
  // Each broken connector takes the radial springs using it at both ends: 3 + 3 inside the sheet,
  // 2 + 2 at its sides.
  EXPECT_EQ(session.simulation().model_changes().broken_radials, 3u * 6u + 2u * 4u);
  EXPECT_LT(session.simulation().energy_balance().fracture_work, 0.0);
  // The lower rows fall away from the anchored part, and the mesh shows two pieces apart.
  const std::vector<Vec3>& position = session.simulation().state().position;
  EXPECT_LT(position[session.particle(3, 2)].y, position[session.particle(2, 2)].y - 0.1);
  SheetMesh mesh;
  build_sheet_mesh(model, position, SheetMeshMode::particles, mesh);
  EXPECT_GT(mesh.vertex_count(), model.particle_count());
  // A reset mends the sheet.
  session.reset();
  EXPECT_TRUE(session.simulation().model().is_intact());
}

TEST(Session, SpringLimitsAreCheckedAndSurviveAReset) {
  Session session(small_scene());
  SpringLimits limits;
  limits.break_strain = 0.5;
  limits.yield_strain = 0.1;
  limits.hardening = 0.2;
  limits.opposite_yield_angle = 0.3;
  ASSERT_EQ(check_spring_limits(limits), "");
  session.set_spring_limits(limits);
  EXPECT_EQ(session.spring_limits(), limits);
  EXPECT_EQ(session.simulation().model().connector_yield_strain[0], 0.1);
  session.reset();
  EXPECT_EQ(session.spring_limits(), limits);
  EXPECT_EQ(session.simulation().model().connector_break_strain[3], 0.5);

  SpringLimits bad = limits;
  bad.yield_strain = 0.8;
  EXPECT_EQ(check_spring_limits(bad), "the yield strain must not exceed the break strain");
  bad = limits;
  bad.break_strain_variation = 1.0;
  EXPECT_EQ(check_spring_limits(bad), "break strain variation must be in [0, 1)");
  bad = limits;
  bad.adjacent_yield_angle = -1.0;
  EXPECT_EQ(check_spring_limits(bad), "yield angles must be >= 0");
  EXPECT_EQ(check_spring_limits(SpringLimits{}), "") << "never tearing nor yielding is valid";
}

}  // namespace
}  // namespace clothsim::viewer
