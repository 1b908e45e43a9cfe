// Behaviour of the adaptive driver: steps land on the requested times, the step floor stops a
// run that cannot meet its tolerance, tighter tolerances give smaller errors, the fused solution
// and error pass matches the plain sums bit for bit, and no step of any integrator allocates.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <vector>

#include "integrators/dynamics.h"
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

// The oracle for the fused solution pass: the whole step of an explicit Runge-Kutta method
// written out particle by particle, without the driver's blocks, pieces, term lists or vector
// loops. Each value is summed as the Nystrom form defines it (explicit_runge_kutta.h): the base,
// then the velocity term, then the accelerations in stage order, zero coefficients left out. So
// the driver, which promises the same sums in the same order, must agree bit for bit.
struct OracleStep {
  std::vector<Vec3> position;  // the trial solution y + h sum b_i k_i, before the anchors are set
  std::vector<Vec3> velocity;
  double error = 0.0;       // max over free particles and coordinates of |e| / (atol + rtol max(|y|, |y_new|))
  std::uint32_t worst = 0;  // the first particle with that error
};

OracleStep oracle_step(const ClothModel& model, const ButcherTableau& tableau, const IntegratorSettings& settings,
                       const ForceOptions& options, const ClothState& state, double h) {
  const std::size_t n = model.particle_count();
  const auto stages = static_cast<std::size_t>(tableau.stages);
  std::vector<StateDerivative> rate(stages);
  for (StateDerivative& k : rate) k.resize(n);
  // (x, v) + h sum_i w_i (V_i, K_i) at particle p, bases null for 0 + ...
  const auto combine = [&](const std::array<double, kMaxStages>& weights, const ClothState* base, std::size_t p,
                           Vec3& x, Vec3& v) {
    const NystromRow row = nystrom_row(tableau, weights);
    x = base != nullptr ? base->position[p] : Vec3{};
    v = base != nullptr ? base->velocity[p] : Vec3{};
    if (row.velocity_sum != 0.0) x = x + (h * row.velocity_sum) * state.velocity[p];
    for (std::size_t l = 0; l < stages; ++l) {
      if (row.position[l] != 0.0) x = x + (h * h * row.position[l]) * rate[l].velocity_rate[p];
      if (row.velocity[l] != 0.0) v = v + (h * row.velocity[l]) * rate[l].velocity_rate[p];
    }
  };
  ClothDynamics dynamics(model, options);
  std::vector<Vec3> stage_position(n);
  std::vector<Vec3> stage_velocity(n);
  for (std::size_t i = 0; i < stages; ++i) {
    for (std::size_t p = 0; p < n; ++p) {
      combine(tableau.coefficients[i], &state, p, stage_position[p], stage_velocity[p]);
    }
    const double stage_time = state.time + tableau.nodes[i] * h;
    dynamics.constrain(stage_time, stage_position, stage_velocity);
    dynamics.evaluate(stage_time, stage_position, stage_velocity, rate[i]);
  }
  OracleStep result;
  result.position.resize(n);
  result.velocity.resize(n);
  std::array<double, kMaxStages> difference{};
  for (std::size_t i = 0; i < stages; ++i) difference[i] = tableau.weights[i] - tableau.embedded_weights[i];
  for (std::size_t p = 0; p < n; ++p) {
    combine(tableau.weights, &state, p, result.position[p], result.velocity[p]);
    if (model.is_anchored(p) || tableau.embedded_order == 0) continue;
    Vec3 error_x;
    Vec3 error_v;
    combine(difference, nullptr, p, error_x, error_v);
    for (int axis = 0; axis < 3; ++axis) {
      for (const auto& [e, before, after] :
           {std::array{error_x[axis], state.position[p][axis], result.position[p][axis]},
            std::array{error_v[axis], state.velocity[p][axis], result.velocity[p][axis]}}) {
        const double scaled = std::abs(e) / (settings.absolute_tolerance +
                                             settings.relative_tolerance * std::max(std::abs(before), std::abs(after)));
        if (scaled > result.error) {
          result.error = scaled;
          result.worst = static_cast<std::uint32_t>(p);
        }
      }
    }
  }
  return result;
}

bool same_bits(const Vec3& a, const Vec3& b) {
  return std::bit_cast<std::array<std::uint64_t, 3>>(std::array{a.x, a.y, a.z}) ==
         std::bit_cast<std::array<std::uint64_t, 3>>(std::array{b.x, b.y, b.z});
}

// A 40 x 40 sheet (1,600 particles: two blocks of the solution pass, the second with a short
// piece) of the paper's material, one anchor fixed and one moving, every particle moving
// differently, and particle 1,300 (in the second block) kicked so that the largest error is near it.
ClothModel moving_sheet() {
  LatticeDef def;
  def.rows = 40;
  def.cols = 40;
  AnchorPath sinusoid;
  sinusoid.kind = AnchorPathKind::sinusoid;
  sinusoid.origin = {-9.5, 0.0, 0.5};  // row 20, col 10, where it rests
  sinusoid.amplitude = {0.0, 0.3, 0.1};
  sinusoid.frequency = 2.0;
  const std::array anchors{Anchor{5, AnchorPath::fixed_at({-14.5, 0.0, -19.5})}, Anchor{810, sinusoid}};
  return build_lattice(def, Environment{}, anchors);
}

ClothState moving_state(const ClothModel& model) {
  ClothState state = make_rest_state(model);
  state.time = 0.25;
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    const auto s = static_cast<double>(p);
    state.position[p] += Vec3{0.01 * std::sin(0.3 * s), 0.02 * std::cos(0.7 * s), 0.01 * std::sin(1.1 * s)};
    state.velocity[p] = Vec3{0.3 * std::sin(0.7 * s), 0.2 * std::cos(1.3 * s), 0.1 * std::sin(2.1 * s)};
  }
  state.velocity[1300] = Vec3{4.0, -3.0, 2.0};
  for (const Anchor& anchor : model.anchors) {
    state.position[anchor.particle] = anchor.path.position(state.time);
    state.velocity[anchor.particle] = anchor.path.velocity_at(state.time);
  }
  return state;
}

// The fused pass (the trial solution and the error norm formed together, block by block and
// piece by piece, on 1 and 2 threads) against the oracle: the same solution, the same error
// norm and the same worst particle, bit for bit.
TEST(AdaptiveRungeKutta, SolutionAndErrorPassMatchTheStraightforwardSums) {
  const ClothModel model = moving_sheet();
  const ClothState start = moving_state(model);
  const double h = 2e-4;
  for (int threads : {1, 2}) {
    ForceOptions options;
    options.threads = threads;
    // An accepted step: the new state is the trial solution, with the anchors on their paths.
    IntegratorSettings loose;
    loose.time_step = h;
    loose.relative_tolerance = loose.absolute_tolerance = 1e-3;
    const OracleStep accepted = oracle_step(model, kFehlberg45, loose, options, start, h);
    ASSERT_GT(accepted.error, 0.0);
    ASSERT_LE(accepted.error, 1.0) << "the oracle's step should be accepted";
    AdaptiveRungeKutta adaptive(model, loose, options, kFehlberg45);
    ClothState state = start;
    ASSERT_EQ(adaptive.step(state, 1.0).status, StepStatus::ok);
    EXPECT_EQ(state.time, start.time + h);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(adaptive.last_error().value), std::bit_cast<std::uint64_t>(accepted.error))
        << adaptive.last_error().value << " " << accepted.error << ", " << threads << " threads";
    for (std::size_t p = 0; p < model.particle_count(); ++p) {
      if (model.is_anchored(p)) continue;
      ASSERT_TRUE(same_bits(state.position[p], accepted.position[p]))
          << "particle " << p << ", " << threads << " threads";
      ASSERT_TRUE(same_bits(state.velocity[p], accepted.velocity[p]))
          << "particle " << p << ", " << threads << " threads";
    }
    EXPECT_EQ(state.position[810], model.anchors[1].path.position(start.time + h));

    // A rejected step, with no smaller step allowed: the run stops naming the worst particle.
    IntegratorSettings tight = loose;
    tight.relative_tolerance = tight.absolute_tolerance = 1e-12;
    tight.min_step = h;
    const OracleStep rejected = oracle_step(model, kFehlberg45, tight, options, start, h);
    ASSERT_GT(rejected.error, 1.0);
    // Near the kicked particle: inside the second block, not at its start, so the driver has to
    // find it there.
    ASSERT_GT(rejected.worst, 1024u);
    AdaptiveRungeKutta failing(model, tight, options, kFehlberg45);
    state = start;
    const StepOutcome outcome = failing.step(state, 1.0);
    EXPECT_EQ(outcome.status, StepStatus::step_underflow);
    EXPECT_EQ(outcome.particle, rejected.worst);
    EXPECT_EQ(failing.last_error().particle, rejected.worst);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(failing.last_error().value), std::bit_cast<std::uint64_t>(rejected.error));

    // The solution pass without error control (fixed steps): RK4, and RKF45's propagated row.
    for (const ButcherTableau* tableau : {&kClassicRk4, &kFehlberg45}) {
      const OracleStep fixed = oracle_step(model, *tableau, loose, options, start, h);
      FixedStepRungeKutta integrator(model, loose, options, *tableau);
      state = start;
      ASSERT_EQ(integrator.step(state, 1.0).status, StepStatus::ok);
      for (std::size_t p = 0; p < model.particle_count(); ++p) {
        if (model.is_anchored(p)) continue;
        ASSERT_TRUE(same_bits(state.position[p], fixed.position[p])) << tableau->name << ", particle " << p;
        ASSERT_TRUE(same_bits(state.velocity[p], fixed.velocity[p])) << tableau->name << ", particle " << p;
      }
    }
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
