// The multigrid V-cycle on the Vulkan device (gpu/device_multigrid.h), the preconditioner of
// implicit Euler's conjugate gradients there, against the CPU's (integrators/multigrid.h): one
// solve converged far below the default tolerance on lattices with one and with several coarse
// levels, odd and even sides; cotton-drape's iterations and frames; the choice between the V-cycle
// and block Jacobi; particles held on a table; a sheet that tears; checkpoints. Level 0 is smoothed
// by single particles (implicit_scenes.h's cotton) or by whole lines, the default
// (integrator.cg_line_smoother), the same on both sides.
#include "gpu/device_multigrid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "core/step_profile.h"
#include "gpu/device_implicit_euler.h"
#include "implicit_scenes.h"
#include "integrators/implicit_euler.h"
#include "io/restored_run.h"
#include "scene/scene_simulation.h"
#include "scene_simulation.h"
#include "sim/simulation.h"

namespace clothsim {
namespace {

using testing::cotton;
using testing::kCpu;
using testing::kVulkan;
using testing::largest_distance;
using testing::table_scene;

gpu::DeviceSelection device0() { return gpu::DeviceSelection{0, Precision::float64, true}; }

// A moving cotton sheet held by two corners, as test_device_implicit_euler.cpp starts its step.
ClothState moving_state(const ClothModel& model) {
  ClothState state;
  state.position = model.particle_rest_position;
  state.velocity.assign(model.particle_count(), Vec3{});
  for (std::size_t p = 0; p < state.velocity.size(); ++p) state.velocity[p] = {0.01 * double(p % 7), -0.2, 0.03};
  return state;
}

// One step from moving_state() on the CPU and on the device, with `settings`.
struct OneStep {
  ImplicitEuler cpu;
  gpu::DeviceImplicitEuler device;
  ClothState cpu_state;
  ClothState device_state;
  OneStep(const ClothModel& model, const IntegratorSettings& settings)
      : cpu(model, settings, ForceOptions{}),
        device(model, settings, ForceOptions{}, device0()),
        cpu_state(moving_state(model)),
        device_state(cpu_state) {
    EXPECT_EQ(cpu.step(cpu_state, 1.0).status, StepStatus::ok);
    EXPECT_EQ(device.step(device_state, 1.0).status, StepStatus::ok);
  }
};

// Whether a and b are within `share` of each other (of the larger).
void expect_within(double a, double b, double share) {
  EXPECT_LE(std::abs(a - b), share * std::max(a, b)) << a << " against " << b;
}

// One step of 1/60 s, the solve converged to 1e-12 with the V-cycle on both sides (threshold 0),
// level 0 smoothed by lines or by single particles on both: 12 x 12 (one coarse level, 6 x 6,
// solved exactly), 33 x 20 (odd and even sides: 17 x 10, then 9 x 5) and 40 x 40 (three coarse
// levels), and with lines strips 2 and 3 nodes wide (lines of 2 and 3 nodes; single particles
// converge there, on 30 x 3, to 5.7e-9 m/s of the CPU's, the strip's conditioning times the
// tolerance). The same matrix and the same cycle up to the sweeps' order (colours here, bands of
// rows on the CPU): the same velocity change, in about as many iterations. Returns the device's
// iterations on each lattice.
std::vector<double> expect_one_solve_is_the_cpus(bool lines) {
  std::vector<std::pair<int, int>> lattices = {{12, 12}, {33, 20}, {40, 40}};
  if (lines) lattices.insert(lattices.end(), {{3, 30}, {30, 3}, {2, 9}});
  std::vector<double> iterations;
  for (const auto& [rows, cols] : lattices) {
    SceneSpec spec = cotton(rows, cols, kCpu, true);
    spec.integrator.cg_line_smoother = lines;
    const ClothModel model = build_model(spec);
    IntegratorSettings settings = spec.integrator;
    settings.cg_tolerance = 1e-12;
    settings.cg_max_iterations = 5000;
    settings.cg_vcycle_threshold = 0.0;
    const OneStep step(model, settings);
    EXPECT_TRUE(step.cpu.last_solve_took_vcycle());
    EXPECT_TRUE(step.device.last_solve_took_vcycle());
    EXPECT_LT(largest_distance(step.cpu_state.velocity, step.device_state.velocity), 1e-9) << rows << " x " << cols;
    EXPECT_LT(largest_distance(step.cpu_state.position, step.device_state.position), 1e-9 / 60.0)
        << rows << " x " << cols;
    expect_within(step.device.last_iterations(), step.cpu.last_iterations(), 0.2);
    // Block Jacobi takes many times as many on the same system.
    settings.cg_two_level = false;
    ClothState jacobi_state = moving_state(model);
    gpu::DeviceImplicitEuler jacobi(model, settings, ForceOptions{}, device0());
    EXPECT_EQ(jacobi.step(jacobi_state, 1.0).status, StepStatus::ok);
    EXPECT_FALSE(jacobi.last_solve_took_vcycle());
    EXPECT_GT(jacobi.last_iterations(), 3 * step.device.last_iterations()) << rows << " x " << cols;
    iterations.push_back(step.device.last_iterations());
  }
  return iterations;
}

TEST(DeviceMultigrid, OneSolveIsTheCpusSolve) {
  // Lines (integrator.cg_line_smoother, the default) take fewer iterations than single particles
  // where the V-cycle has a fine level to smooth (12 x 12 is 2 levels, and its coarse one is exact).
  const std::vector<double> points = expect_one_solve_is_the_cpus(false);
  const std::vector<double> lines = expect_one_solve_is_the_cpus(true);
  for (std::size_t k = 1; k < points.size(); ++k) EXPECT_LT(lines[k], 0.7 * points[k]) << k;
}

// cotton-drape on 24 x 24 for half a second (30 steps of 1/60 s) at the default CG tolerance, with
// the V-cycle, which both sides choose at every step (block Jacobi would take about 12 times the
// iterations: test_device_implicit_euler.cpp), level 0 smoothed by lines or by single particles on
// both. Returns the device's iterations.
double expect_cotton_drape_takes_the_cpus_iterations(bool lines) {
  SceneSpec device_spec = cotton(24, kVulkan, true);
  SceneSpec cpu_spec = cotton(24, kCpu, true);
  device_spec.integrator.cg_line_smoother = cpu_spec.integrator.cg_line_smoother = lines;
  Simulation device = testing::one_thread_simulation(device_spec);
  Simulation cpu = testing::one_thread_simulation(cpu_spec);
  Simulation jacobi = testing::one_thread_simulation(cotton(24, kCpu, false));
  for (int frame = 1; frame <= 30; ++frame) {
    for (Simulation* simulation : {&device, &cpu, &jacobi}) {
      EXPECT_TRUE(simulation->advance_to(frame / 60.0)) << simulation->failure()->message;
    }
    if (frame != 6) continue;
    // Each solve stops at 1e-3 of its right-hand side, so runs that precondition differently part
    // by about that share of a step's velocity change, which grows where the sheet wrinkles (the
    // two cycles sweep in different orders): less than the CPU's own two preconditioners part.
    const double cpu_spread = largest_distance(cpu.state().position, jacobi.state().position);
    EXPECT_LT(largest_distance(device.state().position, cpu.state().position), cpu_spread);
  }
  EXPECT_EQ(device.integrator_stats().accepted_steps, 30u);
  EXPECT_EQ(device.integrator_stats().cg_unconverged_solves, 0u);
  expect_within(static_cast<double>(device.integrator_stats().cg_iterations),
                static_cast<double>(cpu.integrator_stats().cg_iterations), 0.2);
  expect_within(static_cast<double>(device.integrator_stats().cg_max_iterations_in_a_step),
                static_cast<double>(cpu.integrator_stats().cg_max_iterations_in_a_step), 0.2);
  EXPECT_GT(jacobi.integrator_stats().cg_iterations, 5 * device.integrator_stats().cg_iterations);
  return static_cast<double>(device.integrator_stats().cg_iterations);
}

TEST(DeviceMultigrid, CottonDrapeTakesTheCpusIterations) {
  // With lines, the defaults on both sides: 177 iterations on the device, 165 on the CPU
  // (2026-12-05); with single particles 389 and 381.
  EXPECT_TRUE(IntegratorSettings{}.cg_line_smoother);
  const double points = expect_cotton_drape_takes_the_cpus_iterations(false);
  const double lines = expect_cotton_drape_takes_the_cpus_iterations(true);
  EXPECT_LT(lines, 0.6 * points);
}

TEST(DeviceMultigrid, CottonDrapesAsOnTheCpuWithConvergedSolves) {
  // The same sheet for 10 steps with the solves converged to 1e-8 of their right-hand sides: the
  // runs then part by rounding and the solves' remainders alone, and the energy balance's error is
  // backward Euler's, the same on both sides.
  SceneSpec device_spec = cotton(24, kVulkan, true);
  SceneSpec cpu_spec = cotton(24, kCpu, true);
  device_spec.integrator.cg_tolerance = cpu_spec.integrator.cg_tolerance = 1e-8;
  Simulation device = testing::one_thread_simulation(device_spec);
  Simulation cpu = testing::one_thread_simulation(cpu_spec);
  ASSERT_TRUE(device.advance_to(10 / 60.0)) << device.failure()->message;
  ASSERT_TRUE(cpu.advance_to(10 / 60.0)) << cpu.failure()->message;
  EXPECT_LT(largest_distance(device.state().position, cpu.state().position), 1e-6);
  const double balance = device.energy_balance().error();
  const double cpu_balance = cpu.energy_balance().error();
  EXPECT_NEAR(balance, cpu_balance, 1e-3 * std::abs(cpu_balance));
  expect_within(static_cast<double>(device.integrator_stats().cg_iterations),
                static_cast<double>(cpu.integrator_stats().cg_iterations), 0.2);
}

TEST(DeviceMultigrid, ChoosesBetweenTheVcycleAndJacobiAsTheCpu) {
  // The CPU's rule (BlockSystem::setup_preconditioner): the V-cycle where block Jacobi would take
  // more than cg_vcycle_threshold iterations by its estimate. At a frame's step cotton is stiff
  // against its mass (the V-cycle); at 0.1 ms it is mass-dominated (block Jacobi).
  const SceneSpec spec = cotton(24, kCpu, true);
  const ClothModel model = build_model(spec);
  for (const auto& [step, vcycle] : {std::pair{1.0 / 60.0, true}, std::pair{1e-4, false}}) {
    IntegratorSettings settings = spec.integrator;
    settings.time_step = step;
    const OneStep one(model, settings);
    EXPECT_EQ(one.cpu.last_solve_took_vcycle(), vcycle) << step;
    EXPECT_EQ(one.device.last_solve_took_vcycle(), vcycle) << step;
    EXPECT_NEAR(one.device.last_iterations(), one.cpu.last_iterations(), 0.2 * one.cpu.last_iterations());
  }
}

TEST(DeviceMultigrid, HoldsParticlesOnTheTableAsTheCpu) {
  // tablecloth on 15 x 15 for 0.2 s (it lands at 0.1 s) with the V-cycle at every step (threshold 0) on both sides:
  // level 0's rows and columns filtered in the held directions, the coarse levels built from them,
  // and built again after a release. The solves are converged to 1e-8, so that the two cycles'
  // sweeps, in different orders, do not decide differently whether a particle lands a step earlier.
  // Level 0 smoothed by single particles and by lines (whose held particles' line blocks are made
  // invertible along their normals, multigrid_lines.comp).
  for (const bool lines : {false, true}) {
    SceneSpec device_spec = table_scene(kVulkan, true);
    SceneSpec cpu_spec = table_scene(kCpu, true);
    device_spec.integrator.cg_vcycle_threshold = cpu_spec.integrator.cg_vcycle_threshold = 0.0;
    device_spec.integrator.cg_tolerance = cpu_spec.integrator.cg_tolerance = 1e-8;
    device_spec.integrator.cg_line_smoother = cpu_spec.integrator.cg_line_smoother = lines;
    Simulation device = testing::one_thread_simulation(device_spec);
    Simulation cpu = testing::one_thread_simulation(cpu_spec);
    for (int frame = 1; frame <= 4; ++frame) {
      ASSERT_TRUE(device.advance_to(frame * 0.05)) << device.failure()->message;
      ASSERT_TRUE(cpu.advance_to(frame * 0.05)) << cpu.failure()->message;
    }
    EXPECT_LT(largest_distance(device.state().position, cpu.state().position), 1e-6) << lines;
    EXPECT_GT(device.contact_statistics().contact_steps, 0u);
    EXPECT_EQ(device.contact_statistics().contact_steps, cpu.contact_statistics().contact_steps) << lines;
    EXPECT_NEAR(device.state().contact_work, cpu.state().contact_work, 1e-5 * std::abs(cpu.state().contact_work));
    expect_within(static_cast<double>(device.integrator_stats().cg_iterations),
                  static_cast<double>(cpu.integrator_stats().cg_iterations), 0.2);
    testing::expect_resting_on_the_table(device.state().position);
  }
}

TEST(DeviceMultigrid, ASheetTearsAsOnTheCpu) {
  // tear-pull's paper, pulled apart by its anchors, with the V-cycle at every step and the solves
  // converged far below the default tolerance: springs break between the steps (the model's edits
  // reach level 0's rows through the element factors), the same ones as on the CPU.
  SceneSpec spec = builtin_scene("tear-pull");
  spec.integrator.kind = IntegratorKind::implicit_euler;
  spec.integrator.cg_vcycle_threshold = 0.0;
  spec.integrator.cg_tolerance = 1e-8;
  spec.integrator.cg_line_smoother = false;
  spec.collision.self = false;
  spec.colliders.clear();
  SceneSpec on_device = spec;
  on_device.backend = kVulkan;
  Simulation cpu = testing::one_thread_simulation(spec);
  Simulation device = testing::one_thread_simulation(on_device);
  ASSERT_TRUE(cpu.advance_to(0.08)) << cpu.failure()->message;
  ASSERT_TRUE(device.advance_to(0.08)) << device.failure()->message;
  EXPECT_GT(cpu.model_changes().broken_connectors, 10u);
  EXPECT_EQ(device.model_changes().broken_connectors, cpu.model_changes().broken_connectors);
  EXPECT_NEAR(device.model_changes().max_plastic_strain, cpu.model_changes().max_plastic_strain,
              1e-6 * cpu.model_changes().max_plastic_strain);
  EXPECT_LT(largest_distance(cpu.state().position, device.state().position), 1e-3);
  expect_within(static_cast<double>(device.integrator_stats().cg_iterations),
                static_cast<double>(cpu.integrator_stats().cg_iterations), 0.2);
}

// `--profile` names the device's parts of the step as the CPU's (core/step_profile.h), each from
// its passes' timestamps: the Jacobians, the assembly (the right-hand side, level 0 of the V-cycle),
// the preconditioner's setup, the linear solve, the update, and the forces at each step's end.
TEST(DeviceMultigrid, TheProfileNamesTheCpusParts) {
  SceneSpec spec = cotton(24, kVulkan, true);
  spec.integrator.cg_vcycle_threshold = 0.0;  // the V-cycle at every step
  Simulation simulation = testing::one_thread_simulation(spec);
  ASSERT_TRUE(simulation.advance_to(3 / 60.0)) << simulation.failure()->message;
  const StepProfile profile = simulation.profile();
  double parts = 0.0;
  for (StepStage stage : {StepStage::jacobians, StepStage::assembly, StepStage::preconditioner_setup,
                          StepStage::linear_solve, StepStage::solution_update, StepStage::device_steps}) {
    EXPECT_TRUE(profile.timed(stage)) << to_string(stage);
    parts += profile.seconds(stage);
  }
  for (StepStage stage : {StepStage::forces, StepStage::jacobians, StepStage::assembly, StepStage::preconditioner_setup,
                          StepStage::linear_solve}) {
    EXPECT_GT(profile.seconds(stage), 0.0) << to_string(stage);
  }
  // The parts fit inside the integration stage, and the solve, a V-cycle in each of its iterations,
  // is the largest of them.
  EXPECT_LE(parts, profile.seconds(StepStage::integration) * (1.0 + 1e-9) + 1e-6);
  for (StepStage stage : {StepStage::jacobians, StepStage::assembly, StepStage::preconditioner_setup}) {
    EXPECT_GT(profile.seconds(StepStage::linear_solve), profile.seconds(stage)) << to_string(stage);
  }
}

// The levels keep their blocks in single precision, as the CPU's (integrators/stencil_matrix.h):
// 21 blocks of 36 bytes a node over about 4/3 of the particles' nodes, with the vectors and the
// smoother's blocks in float64, about 1.15 kB a particle at 1024 x 1024 (2.2 kB in float64). The
// line smoother adds its factors, 3 blocks a particle in each direction, and one vector: 456 bytes.
TEST(DeviceMultigrid, TheLevelsHoldTheirBlocksInSinglePrecision) {
  const double particles = 1024.0 * 1024.0;
  const double points =
      static_cast<double>(gpu::DeviceMultigrid::bytes_for(1024, 1024, Precision::float64, false)) / particles;
  EXPECT_GT(points, 1000.0);
  EXPECT_LT(points, 1300.0);
  const double lines =
      static_cast<double>(gpu::DeviceMultigrid::bytes_for(1024, 1024, Precision::float64, true)) / particles;
  EXPECT_DOUBLE_EQ(lines - points, 2 * 3 * 9 * 8 + 3 * 8);
}

TEST(DeviceMultigrid, ARestoredRunGoesOnBitForBit) {
  for (const bool lines : {false, true}) {
    SceneSpec spec = cotton(12, kVulkan, true);
    spec.integrator.cg_vcycle_threshold = 0.0;
    spec.integrator.cg_line_smoother = lines;
    testing::expect_restored_run_matches(spec, 0.1, 0.2, 2);
  }
}

}  // namespace
}  // namespace clothsim
