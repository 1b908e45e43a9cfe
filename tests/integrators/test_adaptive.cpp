// Behaviour of the adaptive driver: steps land on the requested times, the step floor stops a
// run that cannot meet its tolerance, tighter tolerances give smaller errors, and no step of any
// integrator allocates.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "integrators/explicit_runge_kutta.h"
#include "integrators/integrator.h"

// Counts every allocation in this test executable, so a test can assert that a code path makes
// none (STYLE.md rule 8: no allocation inside step()).
namespace {
std::atomic<long> g_allocations{0};
}  // namespace
void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace clothsim {
namespace {

// A 4x4 sheet of the paper's material, particle 5 (row 1, col 1) anchored where it starts.
ClothModel small_sheet() {
  LatticeDef def;
  def.rows = 4;
  def.cols = 4;
  const Anchor anchor{5, AnchorPath::fixed_at({-0.5, 0.0, -0.5})};
  return build_lattice(def, Environment{}, {&anchor, 1});
}

TEST(AdaptiveRungeKutta, StepsLandExactlyOnTheLimit) {
  const ClothModel model = small_sheet();
  auto integrator = make_integrator(model, IntegratorSettings{}, ForceOptions{});
  ClothState state = make_rest_state(model);
  for (int frame = 1; frame <= 30; ++frame) {
    const double t = frame / 60.0;
    while (state.time < t) {
      ASSERT_EQ(integrator->step(state, t).status, StepStatus::ok);
      ASSERT_LE(state.time, t);
    }
    EXPECT_EQ(state.time, t);  // exactly, not within rounding
  }
  const IntegratorStats& stats = integrator->stats();
  EXPECT_GT(stats.accepted_steps, 0u);
  EXPECT_EQ(stats.force_evaluations, 6 * (stats.accepted_steps + stats.rejected_steps));
  EXPECT_LE(stats.smallest_step, stats.largest_step);
  // The anchor has not moved.
  EXPECT_EQ(state.position[5], model.particle_rest_position[5]);
}

TEST(AdaptiveRungeKutta, StepFloorEndsTheRunInsteadOfHanging) {
  const ClothModel model = small_sheet();
  IntegratorSettings settings;
  settings.relative_tolerance = 1e-14;
  settings.absolute_tolerance = 1e-14;
  settings.min_step = 1e-3;  // far above what such a tolerance needs
  auto integrator = make_integrator(model, settings, ForceOptions{});
  ClothState state = make_rest_state(model);
  StepOutcome outcome;
  for (int i = 0; i < 1000 && outcome.status == StepStatus::ok; ++i) outcome = integrator->step(state, 1.0);
  EXPECT_EQ(outcome.status, StepStatus::step_underflow);
  EXPECT_LT(outcome.step, settings.min_step);
  EXPECT_LT(outcome.particle, model.particle_count());
  EXPECT_FALSE(model.is_anchored(outcome.particle));
}

TEST(AdaptiveRungeKutta, TighterToleranceGivesSmallerError) {
  const ClothModel model = small_sheet();
  IntegratorSettings reference_settings;
  reference_settings.time_step = 1e-4;
  FixedStepRungeKutta reference(model, reference_settings, ForceOptions{}, kFehlberg45);
  ClothState exact = make_rest_state(model);
  while (exact.time < 0.5) reference.step(exact, 0.5);

  double previous_error = 1e300;
  for (double tolerance : {1e-4, 1e-6, 1e-8}) {
    IntegratorSettings settings;
    settings.relative_tolerance = settings.absolute_tolerance = tolerance;
    auto integrator = make_integrator(model, settings, ForceOptions{});
    ClothState state = make_rest_state(model);
    while (state.time < 0.5) ASSERT_EQ(integrator->step(state, 0.5).status, StepStatus::ok);
    double error = 0.0;
    for (std::size_t p = 0; p < model.particle_count(); ++p)
      error = std::max(error, norm(state.position[p] - exact.position[p]));
    EXPECT_LT(error, previous_error) << "tolerance " << tolerance;
    EXPECT_LT(error, 100 * tolerance) << "tolerance " << tolerance;
    previous_error = error;
  }
}

TEST(Integrators, StepsDoNotAllocate) {
  const ClothModel model = small_sheet();
  for (IntegratorKind kind :
       {IntegratorKind::rkf45, IntegratorKind::rk4, IntegratorKind::symplectic_euler, IntegratorKind::implicit_euler}) {
    IntegratorSettings settings;
    settings.kind = kind;
    settings.time_step = 1e-4;
    auto integrator = make_integrator(model, settings, ForceOptions{});
    ClothState state = make_rest_state(model);
    integrator->step(state, 1.0);
    const long before = g_allocations.load();
    for (int i = 0; i < 100; ++i) integrator->step(state, 1.0);
    EXPECT_EQ(g_allocations.load(), before) << to_string(kind);
  }
}

TEST(IntegratorKind, NamesRoundTrip) {
  for (IntegratorKind kind :
       {IntegratorKind::rkf45, IntegratorKind::rk4, IntegratorKind::symplectic_euler, IntegratorKind::implicit_euler}) {
    IntegratorKind parsed{};
    ASSERT_TRUE(parse_integrator_kind(to_string(kind), parsed));
    EXPECT_EQ(parsed, kind);
  }
  IntegratorKind unused{};
  EXPECT_FALSE(parse_integrator_kind("euler", unused));
}

}  // namespace
}  // namespace clothsim
