// Implicit Euler on the Vulkan backend (gpu/device_implicit_euler.h) on the machine's Vulkan device
// (lavapipe on CI), against the CPU's ImplicitEuler: one step's linear solve, cotton-drape's
// frames, its conjugate-gradient iterations, anchors on paths and their work, sheets that tear
// between steps, checkpoints, and what the backend still refuses.
#include "gpu/device_implicit_euler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "integrators/implicit_euler.h"
#include "io/restored_run.h"
#include "model/cloth_model.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene/scene_simulation.h"
#include "scene/validate_scene.h"
#include "implicit_scenes.h"
#include "scene_simulation.h"
#include "sim/backend.h"
#include "sim/simulation.h"

namespace clothsim {
namespace {

using testing::expect_restored_run_matches;
using testing::largest_distance;

using testing::cotton;
using testing::kCpu;
using testing::kVulkan;
using testing::table_scene;

gpu::DeviceSelection device0() { return gpu::DeviceSelection{0, Precision::float64, true}; }

Vec3 centre_of(const std::vector<Vec3>& x) {
  Vec3 sum;
  for (const Vec3& p : x) sum += p;
  return sum / static_cast<double>(x.size());
}

TEST(DeviceImplicitEuler, OneStepSolvesTheCpusSystem) {
  // One step of 1/60 s from a moving cotton sheet held by two corners, with the solve converged far
  // below its default tolerance: the device's matrix-free products and the CPU's assembled blocks
  // are the same matrix, so both reach the same velocity change.
  const SceneSpec spec = cotton(12, kCpu, false);
  const ClothModel model = build_model(spec);
  IntegratorSettings settings = spec.integrator;
  settings.cg_tolerance = 1e-12;
  settings.cg_max_iterations = 5000;
  ClothState cpu;
  cpu.position = model.particle_rest_position;
  cpu.velocity.assign(model.particle_count(), Vec3{});
  for (std::size_t p = 0; p < cpu.velocity.size(); ++p) cpu.velocity[p] = {0.01 * double(p % 7), -0.2, 0.03};
  ClothState device = cpu;
  ForceOptions options;
  ImplicitEuler reference(model, settings, options);
  gpu::DeviceImplicitEuler integrator(model, settings, options, device0());
  ASSERT_EQ(reference.step(cpu, 1.0).status, StepStatus::ok);
  ASSERT_EQ(integrator.step(device, 1.0).status, StepStatus::ok);
  EXPECT_EQ(cpu.time, device.time);
  EXPECT_LT(largest_distance(cpu.velocity, device.velocity), 1e-9);
  EXPECT_LT(largest_distance(cpu.position, device.position), 1e-11);
  EXPECT_NEAR(cpu.damping_work, device.damping_work, 1e-9 * std::abs(cpu.damping_work));
  EXPECT_NEAR(cpu.anchor_work, device.anchor_work, 1e-9 * std::abs(cpu.damping_work));
  // Block Jacobi on both: the same iterations, give or take the rounding at the tolerance.
  EXPECT_NEAR(integrator.last_iterations(), reference.last_iterations(), 2);
  EXPECT_EQ(integrator.stats().force_evaluations, reference.stats().force_evaluations);
  // And on from there: the warm start and the reused forces of the last step's end.
  for (int k = 0; k < 3; ++k) {
    ASSERT_EQ(reference.step(cpu, 1.0).status, StepStatus::ok);
    ASSERT_EQ(integrator.step(device, 1.0).status, StepStatus::ok);
  }
  EXPECT_LT(largest_distance(cpu.velocity, device.velocity), 1e-7);
  EXPECT_LT(largest_distance(cpu.position, device.position), 1e-9);
  EXPECT_EQ(integrator.stats().force_evaluations, reference.stats().force_evaluations);
}

TEST(DeviceImplicitEuler, CottonDrapeFollowsTheCpu) {
  // cotton-drape on 24 x 24 for half a second (30 steps of 1/60 s) at the default CG tolerance,
  // on the device with block Jacobi alone (cg_two_level false) and on the CPU with the same and
  // with its default multigrid (the device's V-cycle: test_device_multigrid.cpp). Each solve stops at 1e-3 of its right-hand side, so runs that round or
  // precondition differently part by about that share of a step's velocity change, and the parting
  // grows where the sheet wrinkles between its corners: after 0.1 s the CPU's two preconditioners
  // are 8 mm apart and their centres of mass 2 mm.
  Simulation device = testing::one_thread_simulation(cotton(24, kVulkan, false));
  Simulation jacobi = testing::one_thread_simulation(cotton(24, kCpu, false));
  Simulation multigrid = testing::one_thread_simulation(cotton(24, kCpu, true));
  for (int frame = 1; frame <= 30; ++frame) {
    for (Simulation* simulation : {&device, &jacobi, &multigrid}) {
      ASSERT_TRUE(simulation->advance_to(frame / 60.0)) << simulation->failure()->message;
    }
    if (frame != 6) continue;
    // The device follows the CPU's Jacobi run far closer than the CPU's two runs follow each other.
    EXPECT_LT(largest_distance(device.state().position, jacobi.state().position), 1e-3);
    EXPECT_LT(norm(centre_of(device.state().position) - centre_of(jacobi.state().position)), 1e-5);
    const double cpu_spread = largest_distance(jacobi.state().position, multigrid.state().position);
    EXPECT_LT(largest_distance(device.state().position, multigrid.state().position), 1.2 * cpu_spread);
  }
  EXPECT_EQ(device.integrator_stats().accepted_steps, 30u);
  EXPECT_EQ(device.integrator_stats().cg_unconverged_solves, 0u);
  // The CPU's block Jacobi takes the device's iterations within 20 %.
  const double iterations = static_cast<double>(device.integrator_stats().cg_iterations);
  const double cpu_iterations = static_cast<double>(jacobi.integrator_stats().cg_iterations);
  EXPECT_GT(iterations, 0.8 * cpu_iterations) << iterations << " against " << cpu_iterations;
  EXPECT_LT(iterations, 1.2 * cpu_iterations) << iterations << " against " << cpu_iterations;
  // The energy balance, whose error is backward Euler's and the inexact solves', as on the CPU.
  const double balance = device.energy_balance().error();
  const double cpu_balance = jacobi.energy_balance().error();
  EXPECT_NEAR(balance, cpu_balance, 0.02 * std::abs(cpu_balance));
}

TEST(DeviceImplicitEuler, TableclothRestsOnTheTableAsOnTheCpu) {
  // tablecloth on 15 x 15 for 0.3 s (300 steps of 1 ms): the sheet falls 5 cm onto the table, whose
  // top holds the particles resting on it (along the normal, or stuck by friction) while the
  // overhang falls past the edges. The obstacle pass runs on the device after each step.
  Simulation device = testing::one_thread_simulation(table_scene(kVulkan));
  Simulation cpu = testing::one_thread_simulation(table_scene(kCpu));
  for (int frame = 1; frame <= 6; ++frame) {
    ASSERT_TRUE(device.advance_to(frame * 0.05)) << device.failure()->message;
    ASSERT_TRUE(cpu.advance_to(frame * 0.05)) << cpu.failure()->message;
  }
  // The same holds, releases and impulses step by step: the runs part only by rounding (6e-13 m
  // measured on lavapipe, from 1e-16 as the sheet lands).
  EXPECT_LT(largest_distance(device.state().position, cpu.state().position), 1e-9);
  EXPECT_LT(device.state().contact_work, 0.0);
  EXPECT_NEAR(device.state().contact_work, cpu.state().contact_work, 1e-9 * std::abs(cpu.state().contact_work));
  EXPECT_GT(device.contact_statistics().contact_steps, 0u);
  EXPECT_EQ(device.contact_statistics().contact_steps, cpu.contact_statistics().contact_steps);
  const double iterations = static_cast<double>(device.integrator_stats().cg_iterations);
  const double cpu_iterations = static_cast<double>(cpu.integrator_stats().cg_iterations);
  EXPECT_GT(iterations, 0.8 * cpu_iterations) << iterations << " against " << cpu_iterations;
  EXPECT_LT(iterations, 1.2 * cpu_iterations) << iterations << " against " << cpu_iterations;
  testing::expect_resting_on_the_table(device.state().position);
}

TEST(DeviceImplicitEuler, AnAdvanceResolvesTheObstaclesOnTheDevice) {
  // The obstacle pass runs on the device after each step, so one advance takes every step to its
  // limit without the host: tablecloth's 0.2 s, the sheet landing on the table from 5 cm, in one
  // call, with no particle inside the table after it and the contacts counted on the device.
  const SceneSpec spec = table_scene(kVulkan);
  const ClothModel model = build_model(spec);
  ClothState state;
  state.position = model.particle_rest_position;
  state.velocity.assign(model.particle_count(), Vec3{});
  gpu::DeviceImplicitEuler integrator(model, spec.integrator, ForceOptions{}, device0());
  ASSERT_TRUE(integrator.runs_obstacle_contacts());
  const StepOutcome outcome = integrator.advance(state, 0.2);
  ASSERT_EQ(outcome.status, StepStatus::ok);
  EXPECT_DOUBLE_EQ(state.time, 0.2);
  EXPECT_GE(integrator.stats().accepted_steps, 200u);
  testing::expect_resting_on_the_table(state.position);
  const IntegratorContacts contacts = integrator.take_obstacle_contacts();
  EXPECT_GT(contacts.steps, 0u);
  EXPECT_GT(contacts.last, 50u) << "particles on the table at the end";
  EXPECT_LT(state.contact_work, 0.0) << "J: the table stopped the sheet";
}

TEST(DeviceImplicitEuler, AnchorsOnPathsAndTheirWorkFollowTheCpu) {
  // The paper's material shaken by two corners on sinusoids: the anchors' known velocity changes,
  // their columns in the right-hand side and the work they do.
  SceneSpec spec = builtin_scene("paper-fig5");
  spec.lattice.rows = spec.lattice.cols = 9;
  spec.anchors.clear();
  for (int col : {0, 8}) {
    AnchorSpec anchor;
    anchor.row = 0;
    anchor.col = col;
    anchor.path.kind = AnchorPathKind::sinusoid;
    anchor.path.amplitude = {0.0, 0.5, 0.3};
    anchor.path.frequency = 1.5;
    spec.anchors.push_back(anchor);
  }
  spec.integrator.kind = IntegratorKind::implicit_euler;
  spec.integrator.time_step = 1.0 / 120.0;
  spec.integrator.cg_two_level = false;
  spec.environment.air_drag = 0.2;
  SceneSpec on_device = spec;
  on_device.backend = kVulkan;
  Simulation cpu = testing::one_thread_simulation(spec);
  Simulation device = testing::one_thread_simulation(on_device);
  ASSERT_TRUE(cpu.advance_to(1.0));
  ASSERT_TRUE(device.advance_to(1.0)) << device.failure()->message;
  EXPECT_LT(largest_distance(cpu.state().position, device.state().position), 1e-3);
  for (double ClothState::*work : {&ClothState::anchor_work, &ClothState::damping_work, &ClothState::drag_work}) {
    EXPECT_NEAR(device.state().*work, cpu.state().*work, 1e-3 * std::abs(cpu.state().*work) + 1e-6);
  }
  EXPECT_NE(device.state().anchor_work, 0.0);
  EXPECT_NE(device.state().drag_work, 0.0);
}

// tear-pull on the CPU with its laws alone (no obstacle, no self-collision), block Jacobi on both
// sides, the solves converged far below the default tolerance, so that rounding does not move a
// spring across its threshold a step earlier on one side.
SceneSpec tear_pull() {
  SceneSpec spec = builtin_scene("tear-pull");
  spec.integrator.kind = IntegratorKind::implicit_euler;
  spec.integrator.cg_two_level = false;
  spec.integrator.cg_tolerance = 1e-8;
  spec.collision.self = false;
  spec.colliders.clear();
  return spec;
}

TEST(DeviceImplicitEuler, ASheetTearsBetweenTheDevicesSteps) {
  // Tearing and permanent stretching run on the device after each of its steps, as on the CPU
  // after each step: the paper, pulled apart by its anchors, yields and breaks as the CPU's does.
  const SceneSpec spec = tear_pull();
  SceneSpec on_device = spec;
  on_device.backend = kVulkan;
  Simulation cpu = testing::one_thread_simulation(spec);
  Simulation device = testing::one_thread_simulation(on_device);
  // The first 80 steps of 1 ms: the paper yields from 12 ms on and tears from its notch (5 connectors
  // cut before the run) from about 40 ms.
  const double end = 0.08;
  ASSERT_TRUE(cpu.advance_to(end)) << cpu.failure()->message;
  ASSERT_TRUE(device.advance_to(end)) << device.failure()->message;
  EXPECT_GT(cpu.model_changes().broken_connectors, 10u);
  EXPECT_GT(cpu.model_changes().max_plastic_strain, 0.0);
  EXPECT_NEAR(device.model_changes().max_plastic_strain, cpu.model_changes().max_plastic_strain,
              1e-9 * cpu.model_changes().max_plastic_strain);
  EXPECT_EQ(device.model_changes().broken_connectors, cpu.model_changes().broken_connectors);
  EXPECT_LT(largest_distance(cpu.state().position, device.state().position), 1e-3);
}

TEST(DeviceImplicitEuler, WithSelfCollisionTheLawsFollowTheSelfPassOnTheDevice) {
  // The CPU applies the laws after the collision stage. The device runs the self pass itself after
  // each step (gpu/device_implicit_self.cpp) and the laws after it, so both stay on the device with
  // self-collision as without. (Applied before a self pass, the laws left it booking its contact
  // work with the springs of before the step's changes: tear-crumple on 24 x 24 closed its balance
  // to -0.175 J where the CPU's closes to -0.051 J.)
  SceneSpec spec = tear_pull();
  for (bool self : {true, false}) {
    spec.collision.self = self;
    const ClothModel model = build_model(spec);
    gpu::DeviceImplicitEuler integrator(model, spec.integrator, ForceOptions{}, device0());
    EXPECT_TRUE(integrator.runs_spring_events());
    EXPECT_EQ(integrator.runs_self_contacts(), self);
  }
}

TEST(DeviceImplicitEuler, LimitsSetBetweenFramesActOnTheDevice) {
  // tear-pull's paper elastic and unbreakable for 20 ms, then given its limits between two frames
  // (the viewer's panel, a script): the laws' passes act on the device from the next advance on,
  // as the CPU's event stage does.
  const SceneSpec spec = tear_pull();
  const SpringLimits limits = build_model(spec).limits;
  ASSERT_TRUE(limits.changes_sheet());
  SceneSpec elastic = spec;
  set_scene_field(elastic, "springs.connector.break_strain", "none", "test");
  set_scene_field(elastic, "springs.connector.yield_strain", "none", "test");
  set_scene_field(elastic, "springs.adjacent.yield_angle_deg", "none", "test");
  set_scene_field(elastic, "springs.opposite.yield_angle_deg", "none", "test");
  SceneSpec on_device = elastic;
  on_device.backend = kVulkan;
  Simulation cpu = testing::one_thread_simulation(elastic);
  Simulation device = testing::one_thread_simulation(on_device);
  for (Simulation* simulation : {&cpu, &device}) {
    ASSERT_TRUE(simulation->advance_to(0.02)) << simulation->failure()->message;
    EXPECT_EQ(simulation->event_totals().yields, 0u);
    simulation->set_spring_limits(limits);
    ASSERT_TRUE(simulation->advance_to(0.06)) << simulation->failure()->message;
  }
  EXPECT_GT(cpu.event_totals().yields, 0u);
  EXPECT_GT(cpu.model_changes().broken_connectors, 5u);
  EXPECT_EQ(device.event_totals().yields, cpu.event_totals().yields);
  EXPECT_EQ(device.model_changes().broken_connectors, cpu.model_changes().broken_connectors);
  EXPECT_LT(largest_distance(cpu.state().position, device.state().position), 1e-3);
}

TEST(DeviceImplicitEuler, AFilmYieldsOnTheDeviceAndIsLetGoAsOnTheCpu) {
  // film-stretch on 7 x 7: the far row pulled 20 % in 0.5 s on keyframes, the film yielding on the
  // device after each step, and let go at 0.7 s, after which it springs back to its new rest
  // lengths. The device's advances take whole frames (no law on the host), and an anchor let go at
  // the end of one reaches the device with the device's changes to the springs (an edit between
  // two advances once went missing there, and the film stayed stretched, 0.34 J stored).
  SceneSpec spec = builtin_scene("film-stretch");
  const int last = spec.lattice.rows - 1;
  spec.lattice.rows = spec.lattice.cols = 7;
  std::vector<AnchorSpec> anchors;
  for (AnchorSpec anchor : spec.anchors) {
    if (anchor.col >= 7) continue;
    if (anchor.row == last) anchor.row = 6;
    anchors.push_back(anchor);
  }
  spec.anchors = anchors;
  spec.integrator.time_step = 2e-3;
  spec.integrator.cg_tolerance = 1e-9;
  SceneSpec on_device = spec;
  on_device.backend = kVulkan;
  Simulation cpu = testing::one_thread_simulation(spec);
  Simulation device = testing::one_thread_simulation(on_device);
  for (int frame = 1; frame <= 16; ++frame) {
    ASSERT_TRUE(cpu.advance_to(frame * 0.05)) << cpu.failure()->message;
    ASSERT_TRUE(device.advance_to(frame * 0.05)) << device.failure()->message;
  }
  EXPECT_GT(cpu.model_changes().max_plastic_strain, 0.1) << "the film kept a stretch";
  EXPECT_NEAR(device.model_changes().max_plastic_strain, cpu.model_changes().max_plastic_strain,
              1e-6 * cpu.model_changes().max_plastic_strain);
  EXPECT_NEAR(device.state().plastic_work, cpu.state().plastic_work, 1e-6 * std::abs(cpu.state().plastic_work));
  EXPECT_LT(largest_distance(cpu.state().position, device.state().position), 1e-6);
  EXPECT_NEAR(device.energy().connector, cpu.energy().connector, 1e-6 * cpu.energy().connector + 1e-12);
}

TEST(DeviceImplicitEuler, ARestoredRunGoesOnBitForBit) {
  expect_restored_run_matches(cotton(12, kVulkan, true), 0.1, 0.2, 2);
  // With particles held on the table: the slipped flags go with the checkpoint.
  EXPECT_GT(expect_restored_run_matches(table_scene(kVulkan), 0.12, 0.16, 2).contact_steps, 0u);
  // With the laws on the device: the model's changes go with the checkpoint and up again. Saved as
  // the paper yields, going on as it starts to tear (about 40 ms).
  SceneSpec tearing = tear_pull();
  tearing.backend = kVulkan;
  expect_restored_run_matches(tearing, 0.03, 0.05, 2);
}

TEST(DeviceImplicitEuler, RefusesWhatItCannotRun) {
  const auto refusal = [](const SceneSpec& spec) { return testing::refusal_of(spec); };
  // float32, as on the CPU; unset, the backend gives implicit Euler float64.
  SceneSpec float32 = cotton(8, BackendSettings{Backend::vulkan, 0, request(Precision::float32)}, true);
  EXPECT_NE(refusal(float32).find("float32 (precision) with implicit-euler"), std::string::npos)
      << refusal(float32);
  EXPECT_EQ(refusal(cotton(8, kVulkan, true)), "no refusal");
  // Every built-in scene runs on the device (self-collision on the host between its steps).
  for (const BuiltinScene& scene : builtin_scenes()) {
    SceneSpec spec = builtin_scene(scene.name);
    spec.backend = kVulkan;
    EXPECT_EQ(refusal(spec), "no refusal") << scene.name;
  }
}

}  // namespace
}  // namespace clothsim
