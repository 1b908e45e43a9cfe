// The lattice path's stages in one pass each and chained several to a pass (lattice_stage.comp)
// against the three passes each they replace (rk_stage_state, lattice_elements,
// stage_acceleration; issue 22 item 1). lattice_stage forms the stage states and the neighbours'
// spring sums itself, with the same functions and in the same order, so each attempt gives the
// same bits; the step control then takes the same steps, and a whole run is the same run. Held bit for bit in both
// precisions, on sheets that reach every case the pass has: edges and corners on each side of a lattice that is not
// square, anchors on each kind of path and one let go, springs torn, yielded and creased between steps (each particle
// reading its own springs), and a uniform sheet (every particle reading one particle's springs).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "collision/obstacle_fixtures.h"
#include "device_models.h"
#include "gpu/device_integrator.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene/validate_scene.h"
#include "scene_simulation.h"
#include "sim/simulation.h"

namespace clothsim {
namespace {

using testing::paper_lattice;
using testing::run_scene_to;
using testing::RunEnd;
using testing::vulkan;

BackendSettings device(Precision precision, StagePasses passes) {
  BackendSettings backend = vulkan(precision);
  backend.stage_passes = passes;
  return backend;
}

// The ways lattice_stage runs the stages in `precision`, each held against three passes a stage
// (float64 chains one stage a pass: the same passes as one pass a stage).
std::vector<StagePasses> one_pass_ways(Precision precision) {
  if (precision == Precision::float64) return {StagePasses::fused};
  return {StagePasses::fused, StagePasses::chained};
}

// A 10 x 13 sheet pulled by anchors on a line, a sinusoid and keyframes, with one anchor let go
// at 0.1 s, that tears (break strain 4 % +- 30 %), yields (2 %, hardening 0.5) and creases (2
// degrees).
SceneSpec changing_sheet(const BackendSettings& backend) {
  SceneSpec spec = scene_from_paper_args("10,13,1,4,1,1400,200,80,5,1", "test");
  set_scene_field(spec, "anchors",
                  R"([{"row": 0, "col": 0, "path": {"type": "linear", "velocity": [0.2, 0.1, 0]}},
                      {"row": 0, "col": 12, "path": {"type": "sinusoid", "amplitude": [0, 0.3, 0.1], "frequency": 3,
                                                     "phase": 0.4}},
                      {"row": 0, "col": 6, "release_time": 0.1},
                      {"row": 9, "col": 0, "path": {"type": "keyframes", "keys": [[0, 0, 0, 0], [0.3, 0, -2, 0]]}},
                      {"row": 9, "col": 12, "path": {"type": "keyframes", "keys": [[0, 0, 0, 0], [0.3, 0, -2, 0]]}}])",
                  "test");
  set_scene_field(spec, "springs.connector.break_strain", "0.04", "test");
  set_scene_field(spec, "springs.connector.break_strain_variation", "0.3", "test");
  set_scene_field(spec, "springs.connector.yield_strain", "0.02", "test");
  set_scene_field(spec, "springs.connector.hardening", "0.5", "test");
  set_scene_field(spec, "springs.adjacent.yield_angle_deg", "2", "test");
  set_scene_field(spec, "springs.opposite.yield_angle_deg", "2", "test");
  validate_scene(spec, "test");
  spec.backend = backend;
  return spec;
}

// The first particle whose position or velocity differs in any bit, or -1.
long first_difference(const std::vector<Vec3>& position_a, const std::vector<Vec3>& velocity_a,
                      const std::vector<Vec3>& position_b, const std::vector<Vec3>& velocity_b) {
  for (std::size_t p = 0; p < position_a.size(); ++p) {
    if (!(position_a[p] == position_b[p]) || !(velocity_a[p] == velocity_b[p])) return static_cast<long>(p);
  }
  return -1;
}

long first_difference(const ClothState& a, const ClothState& b) {
  return first_difference(a.position, a.velocity, b.position, b.velocity);
}

void expect_same_run(const RunEnd& fused, const RunEnd& split, const char* what) {
  EXPECT_EQ(first_difference(fused.position, fused.velocity, split.position, split.velocity), -1) << what;
  EXPECT_EQ(fused.stats.accepted_steps, split.stats.accepted_steps) << what;
  EXPECT_EQ(fused.stats.rejected_steps, split.stats.rejected_steps) << what;
  EXPECT_EQ(fused.stats.force_evaluations, split.stats.force_evaluations) << what;
  EXPECT_EQ(fused.events.breaks, split.events.breaks) << what;
  EXPECT_EQ(fused.events.yields, split.events.yields) << what;
  EXPECT_EQ(fused.events.creases, split.events.creases) << what;
  EXPECT_EQ(fused.live, split.live) << what;
  EXPECT_EQ(fused.rest_length, split.rest_length) << what;
  EXPECT_EQ(fused.rest_angle, split.rest_angle) << what;
  EXPECT_EQ(fused.fracture_work, split.fracture_work) << what;
  EXPECT_EQ(fused.plastic_work, split.plastic_work) << what;
  EXPECT_EQ(fused.balance_error, split.balance_error) << what;
}

TEST(DeviceFusedStages, ASheetThatTearsYieldsAndCreasesOnPathsRunsTheSameBits) {
  for (Precision precision : {Precision::float64, Precision::float32}) {
    const RunEnd split = run_scene_to(changing_sheet(device(precision, StagePasses::split)), 0.3);
    std::printf("%s: %llu steps, %zu breaks, %zu yields, %zu creases\n", to_string(precision),
                static_cast<unsigned long long>(split.stats.accepted_steps), split.events.breaks, split.events.yields,
                split.events.creases);
    ASSERT_GT(split.events.breaks, 0u) << "the sheet tears";
    ASSERT_GT(split.events.yields, 0u) << "the sheet yields";
    ASSERT_GT(split.events.creases, 0u) << "the sheet creases";
    for (StagePasses passes : one_pass_ways(precision)) {
      const RunEnd one = run_scene_to(changing_sheet(device(precision, passes)), 0.3);
      expect_same_run(one, split, (std::string(to_string(precision)) + " " + to_string(passes)).c_str());
    }
  }
}

TEST(DeviceFusedStages, AUniformSheetRunsTheSameBits) {
  for (Precision precision : {Precision::float64, Precision::float32}) {
    SceneSpec spec = builtin_scene("paper-fig5");
    spec.backend = device(precision, StagePasses::split);
    const RunEnd split = run_scene_to(spec, 0.25);
    for (StagePasses passes : one_pass_ways(precision)) {
      spec.backend = device(precision, passes);
      expect_same_run(run_scene_to(spec, 0.25), split,
                      (std::string(to_string(precision)) + " " + to_string(passes)).c_str());
    }
  }
}

// The obstacle pass reads the trial state the last stage's pass forms: paper-fig5 folding onto a
// sphere under one side (its top 0.5 m below the sheet) runs the same bits either way.
TEST(DeviceFusedStages, ASheetOnAnObstacleRunsTheSameBits) {
  for (Precision precision : {Precision::float64, Precision::float32}) {
    SceneSpec spec = builtin_scene("paper-fig5");
    set_scene_field(spec, "springs.opposite.damping", "20", "test");
    ColliderSpec ball;
    ball.collider = obstacle_fixtures::sphere({3.0, -2.5, 0.0}, 2.0);
    spec.colliders.push_back(ball);
    spec.backend = device(precision, StagePasses::split);
    const RunEnd split = run_scene_to(spec, 0.5);
    ASSERT_GT(split.contact_steps, 0u) << "the sheet reaches the sphere";
    for (StagePasses passes : one_pass_ways(precision)) {
      spec.backend = device(precision, passes);
      const RunEnd one = run_scene_to(spec, 0.5);
      const std::string what = std::string(to_string(precision)) + " " + to_string(passes);
      expect_same_run(one, split, what.c_str());
      EXPECT_EQ(one.contact_steps, split.contact_steps) << what;
    }
  }
}

// RK4 and symplectic Euler take lattice_stage too, in one pass a stage and chained: 30 steps from
// a deformed, moving sheet of 20 x 22, whose middle tile's regions (four cells around it for
// chained float32's first stage) lie inside the lattice, and whose edge tiles are cut.
TEST(DeviceFusedStages, EveryExplicitMethodTakesTheSameSteps) {
  const ClothModel model = paper_lattice(20, 22);
  for (IntegratorKind kind : {IntegratorKind::symplectic_euler, IntegratorKind::rk4, IntegratorKind::rkf45}) {
    IntegratorSettings settings;
    settings.kind = kind;
    settings.time_step = 2e-4;
    for (Precision precision : {Precision::float64, Precision::float32}) {
      std::vector<ClothState> ends;
      for (StagePasses passes : {StagePasses::split, StagePasses::fused, StagePasses::chained}) {
        gpu::DeviceSelection selection{0, precision, true};
        selection.stage_passes = passes;
        gpu::DeviceIntegrator integrator(model, settings, ForceOptions{}, selection);
        ClothState state;
        state.position = model.particle_rest_position;
        state.velocity.resize(model.particle_count());
        for (std::size_t p = 0; p < state.position.size(); ++p) {  // stretched, sheared and bent, moving
          const double s = static_cast<double>(p);
          state.position[p] += Vec3{0.05 * std::sin(s), 0.08 * std::cos(0.7 * s), 0.03 * std::sin(1.3 * s)};
          state.velocity[p] = Vec3{0.3 * std::cos(s), -0.2, 0.4 * std::sin(0.5 * s)};
        }
        for (int k = 1; k <= 30; ++k) ASSERT_EQ(integrator.step(state, k * 2e-4).status, StepStatus::ok);
        ends.push_back(state);
      }
      EXPECT_EQ(first_difference(ends[1], ends[0]), -1) << to_string(kind) << " fused, " << to_string(precision);
      EXPECT_EQ(first_difference(ends[2], ends[0]), -1) << to_string(kind) << " chained, " << to_string(precision);
    }
  }
}

// The last stage's pass forms the trial state and each tile's largest error (rk_solution's work):
// a run that blows up (RK4 at 10 ms steps) and one whose step underflows (RKF45 asked for 1e-14)
// stop at the same time and step with the same diagnosis, naming the same particle, as with
// rk_solution's workgroups of 256 particles.
TEST(DeviceFusedStages, AFailureIsDiagnosedAsWithThreePasses) {
  const auto failure = [](Precision precision, StagePasses passes, bool underflow) {
    SceneSpec spec = builtin_scene("paper-fig5");
    spec.backend = device(precision, passes);
    if (underflow) {
      spec.integrator.relative_tolerance = spec.integrator.absolute_tolerance = 1e-14;
      spec.integrator.min_step = spec.integrator.time_step = 1e-4;
    } else {
      spec.integrator.kind = IntegratorKind::rk4;
      spec.integrator.time_step = 0.01;
    }
    Simulation simulation = make_simulation(spec);
    bool failed = false;
    for (int frame = 1; frame <= 30 && !failed; ++frame) failed = !simulation.advance_to(frame / 60.0);
    EXPECT_TRUE(failed);
    return simulation.failure();
  };
  for (Precision precision : {Precision::float64, Precision::float32}) {
    for (bool underflow : {false, true}) {
      const std::optional<Diagnosis> split = failure(precision, StagePasses::split, underflow);
      ASSERT_TRUE(split.has_value()) << to_string(precision);
      std::printf("%s: %s (%s)\n", to_string(precision), split->message.c_str(), split->element.c_str());
      EXPECT_NE(split->message.find(underflow ? "step size underflow" : "blown up"), std::string::npos)
          << split->message;
      for (StagePasses passes : one_pass_ways(precision)) {
        const std::optional<Diagnosis> one = failure(precision, passes, underflow);
        const std::string what = std::string(to_string(precision)) + " " + to_string(passes);
        ASSERT_TRUE(one.has_value()) << what;
        EXPECT_EQ(one->time, split->time) << what;
        EXPECT_EQ(one->step, split->step) << what;
        EXPECT_EQ(one->message, split->message) << what;
        EXPECT_EQ(one->element, split->element) << what;
      }
    }
  }
}

// In one pass a stage, an RKF45 attempt moves less than half the bytes a particle of three passes
// a stage (counted from the passes' arrays), and chained (three stages a pass in float32, one in
// float64) less again; its profile has lattice_stage's passes under "forces". Unasked, a GPU
// chains the stages and a CPU device (lavapipe) splits them.
TEST(DeviceFusedStages, AnAttemptMovesLessThanHalfTheBytes) {
  const ClothModel model = paper_lattice(8, 8);
  for (Precision precision : {Precision::float32, Precision::float64}) {
    const std::optional<StagePasses> choices[] = {StagePasses::split, StagePasses::fused, StagePasses::chained,
                                                  std::nullopt};
    double traffic[4] = {0.0, 0.0, 0.0, 0.0};
    bool cpu_device = false;
    for (int choice = 0; choice < 4; ++choice) {
      gpu::DeviceSelection selection{0, precision, true};
      selection.stage_passes = choices[choice];
      gpu::DeviceIntegrator integrator(model, IntegratorSettings{}, ForceOptions{}, selection);
      ClothState state;
      state.position = model.particle_rest_position;
      state.velocity.assign(model.particle_count(), Vec3{});
      ASSERT_EQ(integrator.step(state, 0.01).status, StepStatus::ok);
      traffic[choice] = integrator.traffic_per_particle_and_attempt();
      cpu_device = integrator.device_info().type == "cpu";
      if (choice == 3) continue;
      const StepProfile& profile = integrator.profile();
      EXPECT_GT(profile.seconds(StepStage::forces), 0.0);
      EXPECT_EQ(profile.timed(StepStage::stage_sums), choice == 0) << "the stage sums are lattice_stage's";
    }
    EXPECT_EQ(traffic[3], traffic[cpu_device ? 0 : 2]) << "unasked, " << (cpu_device ? "split" : "chained");
    std::printf("%s: %.0f bytes a particle and attempt chained, %.0f in one pass a stage, %.0f in three\n",
                to_string(precision), traffic[2], traffic[1], traffic[0]);
    EXPECT_LT(traffic[1], 0.5 * traffic[0]) << to_string(precision);
    if (precision == Precision::float32) {
      EXPECT_LT(traffic[2], 0.8 * traffic[1]);
    } else {
      EXPECT_EQ(traffic[2], traffic[1]) << "float64 chains one stage a pass";
    }
  }
}

}  // namespace
}  // namespace clothsim
