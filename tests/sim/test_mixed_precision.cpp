// Float32 forces on the CPU (`precision float32`: the lattice kernel's springs in float, the state,
// the stage sums and the error norm in double) through whole runs, and `auto`'s rule.
//
// The paper's three scenes (paper-fig4 without its self-collision) for a quarter second at the
// default tolerances, against the float64 run. The two differ by the forces' rounding, about
// 1e-6 of the largest force (tests/forces/test_float32_forces.cpp), integrated: measured 1.9e-7 m
// (fig6) to 1.1e-6 m (fig4) and 2.7e-5 m/s, on sheets of 5 to 10 m, against RKF45's own error of
// about 1e-6 m at these tolerances (docs/performance.md, "Mixed precision"); bound 1e-5 m and
// 1e-4 m/s. The energy balance closes within 1e-8 of the energy scale (measured errors 0.5 to
// 2.8 microjoules, float64's 0.5 to 1.9), and the error control takes within 5 % of float64's
// steps (measured 2 %): float32 forces do not spoil the default tolerances.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene_simulation.h"
#include "sim/backend.h"

namespace clothsim {
namespace {

using testing::largest_distance;
using testing::run_scene_to;
using testing::RunEnd;

// On one thread, so that the figures do not depend on the machine's load.
RunEnd run_to(SceneSpec spec, PrecisionRequest precision, double t) {
  spec.backend.precision = precision;
  spec.threads = 1;
  return run_scene_to(spec, t);
}

TEST(MixedPrecision, PaperScenesInFloat32StayWithTheFloat64Runs) {
  for (const char* name : {"paper-fig4", "paper-fig5", "paper-fig6"}) {
    SceneSpec spec = builtin_scene(name);
    spec.collision.self = false;
    const RunEnd f64 = run_to(spec, PrecisionRequest::float64, 0.25);
    const RunEnd f32 = run_to(spec, PrecisionRequest::float32, 0.25);
    const double distance = largest_distance(f64.position, f32.position);
    const double speed = largest_distance(f64.velocity, f32.velocity);
    std::printf("%s: largest distance %.3g m, velocity %.3g m/s; steps %llu vs %llu; balance %.3g vs %.3g J\n", name,
                distance, speed, static_cast<unsigned long long>(f32.stats.accepted_steps),
                static_cast<unsigned long long>(f64.stats.accepted_steps), f32.balance_error, f64.balance_error);
    EXPECT_LT(distance, 1e-5) << name;
    EXPECT_LT(speed, 1e-4) << name;
    EXPECT_LT(std::abs(f32.balance_error), 1e-8 * f32.energy_scale) << name;
    EXPECT_NEAR(static_cast<double>(f32.stats.accepted_steps), static_cast<double>(f64.stats.accepted_steps),
                0.05 * static_cast<double>(f64.stats.accepted_steps))
        << name;
  }
}

// `auto`: float32 for RKF45 at tolerances of 1e-6 or looser (both), float64 otherwise and for the
// methods that ask for no accuracy, and on the CPU for a sheet that is not a lattice; an unset
// precision is `auto` on the CPU and float32 on a device. The CPU's float32 under `auto` is
// chosen frame by frame; an explicit float32 is not.
TEST(MixedPrecision, AutoPicksFloat32OnlyWhereTheTolerancesAllowIt) {
  IntegratorSettings settings;  // rkf45, rtol = atol = 1e-6
  const BackendSettings automatic{Backend::cpu, 0, PrecisionRequest::automatic};
  EXPECT_EQ(automatic.resolved_precision(settings, true), Precision::float32);
  EXPECT_TRUE(automatic.chooses_by_frame(settings, true));
  EXPECT_EQ(automatic.resolved_precision(settings, false), Precision::float64);
  EXPECT_FALSE(automatic.chooses_by_frame(settings, false));
  settings.relative_tolerance = 1e-4;
  EXPECT_EQ(automatic.resolved_precision(settings, true), Precision::float32);
  settings.absolute_tolerance = 1e-7;
  EXPECT_EQ(automatic.resolved_precision(settings, true), Precision::float64);
  EXPECT_FALSE(automatic.chooses_by_frame(settings, true));
  settings.absolute_tolerance = 1e-3;
  settings.relative_tolerance = 1e-8;
  EXPECT_EQ(automatic.resolved_precision(settings, true), Precision::float64);
  for (IntegratorKind kind :
       {IntegratorKind::rk4, IntegratorKind::symplectic_euler, IntegratorKind::implicit_euler, IntegratorKind::imex}) {
    IntegratorSettings fixed;
    fixed.kind = kind;
    EXPECT_EQ(automatic.resolved_precision(fixed, true), Precision::float64) << to_string(kind);
    EXPECT_FALSE(automatic.chooses_by_frame(fixed, true)) << to_string(kind);
  }
  EXPECT_EQ(BackendSettings{}.resolved_precision(IntegratorSettings{}, true), Precision::float32);
  EXPECT_TRUE(BackendSettings{}.chooses_by_frame(IntegratorSettings{}, true));
  EXPECT_EQ(BackendSettings{}.resolved_precision(IntegratorSettings{}, false), Precision::float64);
  const BackendSettings float32{Backend::cpu, 0, PrecisionRequest::float32};
  EXPECT_EQ(float32.resolved_precision(IntegratorSettings{}, true), Precision::float32);
  EXPECT_FALSE(float32.chooses_by_frame(IntegratorSettings{}, true));
  const BackendSettings device{Backend::vulkan, 0, std::nullopt};
  EXPECT_EQ(device.resolved_precision(IntegratorSettings{}, true), Precision::float32);
  EXPECT_FALSE(device.chooses_by_frame(IntegratorSettings{}, true));
}

// A run asked for float32 uses float32 forces; implicit Euler and sheets that are not lattices
// are refused float32 with the reason, and `auto` gives implicit Euler float64.
TEST(MixedPrecision, Float32IsTheExplicitMethodsOnALattice) {
  SceneSpec spec = builtin_scene("paper-fig5");
  spec.backend.precision = PrecisionRequest::float32;
  for (IntegratorKind kind : {IntegratorKind::rkf45, IntegratorKind::rk4, IntegratorKind::symplectic_euler}) {
    spec.integrator.kind = kind;
    spec.integrator.time_step = 1e-4;
    EXPECT_TRUE(unsupported_by_backend(BackendFeatures{spec.integrator, {}, false, false, true}, spec.backend).empty());
    Simulation simulation = testing::one_thread_simulation(spec);
    ASSERT_TRUE(simulation.advance_to(0.01)) << to_string(kind);
  }
  spec.integrator.kind = IntegratorKind::implicit_euler;
  const std::string refused =
      unsupported_by_backend(BackendFeatures{spec.integrator, {}, false, false, true}, spec.backend);
  EXPECT_NE(refused.find("float32 (precision) with implicit-euler (integrator.method)"), std::string::npos) << refused;
  EXPECT_THROW(testing::one_thread_simulation(spec), BackendError);
  const std::string not_lattice =
      unsupported_by_backend(BackendFeatures{IntegratorSettings{}, {}, false, false, false}, spec.backend);
  EXPECT_NE(not_lattice.find("not a lattice"), std::string::npos) << not_lattice;
  spec.backend.precision = PrecisionRequest::automatic;
  EXPECT_NO_THROW(testing::one_thread_simulation(spec));
}

}  // namespace
}  // namespace clothsim
