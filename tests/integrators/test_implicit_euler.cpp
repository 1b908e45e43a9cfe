// Implicit Euler (one Newton step, conjugate gradients): it dissipates energy on a damped sheet,
// converges at first order to the RKF45 solution, stays stable on stiff cotton at the frame step
// where RK4 blows up, keeps anchors exactly on their paths, books the damping work at the end of
// the step, and gives the same bits for any thread count.
#include "integrators/implicit_euler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "forces/forces.h"
#include "integrators/integrator.h"
#include "model/material.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene/scene_model.h"
#include "sim/simulation.h"

namespace clothsim {
namespace {

// A sheet of the paper's material with the two corners of row 0 anchored where they start.
ClothModel corner_sheet(int rows, int cols, const LatticeDef& material = LatticeDef{}) {
  LatticeDef def = material;
  def.rows = rows;
  def.cols = cols;
  const ClothModel flat = build_lattice(def, Environment{}, {});
  const std::uint32_t right = lattice_index(cols, 0, cols - 1);
  const Anchor anchors[2] = {{0, AnchorPath::fixed_at(flat.particle_rest_position[0])},
                             {right, AnchorPath::fixed_at(flat.particle_rest_position[right])}};
  return build_lattice(def, Environment{}, anchors);
}

IntegratorSettings implicit_settings(double step, double tolerance = 1e-10) {
  IntegratorSettings settings;
  settings.kind = IntegratorKind::implicit_euler;
  settings.time_step = step;
  settings.cg_tolerance = tolerance;
  settings.cg_max_iterations = 10000;
  return settings;
}

double max_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double distance = 0.0;
  for (std::size_t p = 0; p < a.size(); ++p) distance = std::max(distance, norm(a[p] - b[p]));
  return distance;
}

// The cotton-drape scene on a smaller lattice (same spacing and springs, so the same stiffness
// per particle), anchors re-resolved for the new size.
SceneSpec small_cotton(int size) {
  SceneSpec spec = builtin_scene("cotton-drape");
  spec.lattice.rows = spec.lattice.cols = size;
  parse_anchor_preset("edge-corners", spec.lattice, spec.anchors);
  return spec;
}

TEST(ImplicitEuler, EnergyDecreasesMonotonicallyOnADampedSheet) {
  const ClothModel model = corner_sheet(8, 8);
  ImplicitEuler integrator(model, implicit_settings(1.0 / 60.0), ForceOptions{});
  ClothState state = make_rest_state(model);
  double previous = compute_energy(model, state).total();
  for (int step = 0; step < 240; ++step) {
    ASSERT_EQ(integrator.step(state, 10.0).status, StepStatus::ok);
    const double energy = compute_energy(model, state).total();  // kinetic + gravity + springs
    EXPECT_LE(energy, previous) << "step " << step;
    previous = energy;
  }
  // It has lost a good part of the potential energy it started falling with.
  EXPECT_LT(previous, -100.0);
}

TEST(ImplicitEuler, ConvergesToTheRkf45SolutionAtFirstOrder) {
  const ClothModel model = corner_sheet(4, 5);
  const double end = 0.25;
  IntegratorSettings reference_settings;
  reference_settings.relative_tolerance = reference_settings.absolute_tolerance = 1e-11;
  auto reference = make_integrator(model, reference_settings, ForceOptions{});
  ClothState exact = make_rest_state(model);
  while (exact.time < end) ASSERT_EQ(reference->step(exact, end).status, StepStatus::ok);

  std::vector<double> errors;
  for (const double step : {1.0 / 400, 1.0 / 800, 1.0 / 1600, 1.0 / 3200}) {
    ImplicitEuler integrator(model, implicit_settings(step, 1e-12), ForceOptions{});
    ClothState state = make_rest_state(model);
    while (state.time < end) ASSERT_EQ(integrator.step(state, end).status, StepStatus::ok);
    errors.push_back(max_distance(state.position, exact.position));
  }
  for (std::size_t i = 1; i < errors.size(); ++i) {
    const double ratio = errors[i - 1] / errors[i];
    EXPECT_GT(ratio, 1.8) << "halving the step from error " << errors[i - 1];
    EXPECT_LT(ratio, 2.2) << "halving the step from error " << errors[i - 1];
  }
  EXPECT_LT(errors.back(), 1e-2);
}

TEST(ImplicitEuler, StiffCottonIsStableAtTheFrameStepWhereRk4BlowsUp) {
  const SceneSpec spec = small_cotton(12);
  ASSERT_EQ(spec.integrator.kind, IntegratorKind::implicit_euler);
  ASSERT_EQ(spec.integrator.time_step, 1.0 / 60.0);

  SimulationSettings settings;
  settings.integrator = spec.integrator;
  const ClothModel model = build_model(spec);
  Simulation implicit(model, build_initial_state(model, spec), settings);
  // The sheet's whole potential energy scale: its mass falling by its own size.
  double mass = 0.0;
  for (double m : model.particle_mass) mass += m;
  const double scale = mass * 9.81 * spec.lattice.spacing * spec.lattice.rows;
  for (int frame = 1; frame <= 180; ++frame) {
    ASSERT_TRUE(implicit.advance_to(frame / 60.0)) << implicit.failure()->message;
    const EnergyReport energy = implicit.energy();
    ASSERT_TRUE(std::isfinite(energy.total()));
    EXPECT_LT(energy.kinetic, scale) << "frame " << frame;
    // The first steps stretch the connectors next to the anchors beyond the physical sag: one
    // Newton step moves particles along the tangent of springs at rest length, which have no
    // sideways stiffness yet (docs/materials.md). Bounded, and damped out within a few frames.
    EXPECT_LT(energy.connector + energy.radial_adjacent + energy.radial_opposite, 10 * scale) << "frame " << frame;
  }
  EXPECT_EQ(implicit.integrator_stats().cg_unconverged_solves, 0u);
  EXPECT_GT(implicit.integrator_stats().cg_iterations, 0u);
  // Nearly at rest after 3 s.
  EXPECT_LT(implicit.energy().kinetic, 1e-3 * scale);

  // RK4 at the same step: the connectors' period is far below 1/60 s.
  settings.integrator.kind = IntegratorKind::rk4;
  Simulation explicit_rk4(model, build_initial_state(model, spec), settings);
  bool ok = true;
  for (int frame = 1; frame <= 180 && ok; ++frame) ok = explicit_rk4.advance_to(frame / 60.0);
  EXPECT_FALSE(ok);
  ASSERT_TRUE(explicit_rk4.failure().has_value());
  EXPECT_LT(explicit_rk4.failure()->time, 0.5);
}

TEST(ImplicitEuler, AnchorsStayExactlyOnTheirPaths) {
  LatticeDef def;
  def.rows = 6;
  def.cols = 6;
  const ClothModel flat = build_lattice(def, Environment{}, {});
  AnchorPath moving;
  moving.kind = AnchorPathKind::sinusoid;
  moving.origin = flat.particle_rest_position[5];
  moving.amplitude = {0.0, 0.8, 0.3};
  moving.frequency = 1.3;
  moving.phase = 0.4;
  AnchorPath sliding;
  sliding.kind = AnchorPathKind::linear;
  sliding.origin = flat.particle_rest_position[0];
  sliding.velocity = {0.5, 0.0, -0.2};
  const Anchor anchors[2] = {{0, sliding}, {5, moving}};
  const ClothModel model = build_lattice(def, Environment{}, anchors);
  ImplicitEuler integrator(model, implicit_settings(0.01, 1e-6), ForceOptions{});
  ClothState state = make_rest_state(model);
  for (int frame = 1; frame <= 60; ++frame) {
    const double t = frame / 60.0;
    while (state.time < t) ASSERT_EQ(integrator.step(state, t).status, StepStatus::ok);
    for (const Anchor& anchor : model.anchors) {
      EXPECT_EQ(state.position[anchor.particle], anchor.path.position(state.time));
      EXPECT_EQ(state.velocity[anchor.particle], anchor.path.velocity_at(state.time));
    }
  }
}

TEST(ImplicitEuler, DampingWorkUsesTheEndOfStepPower) {
  const ClothModel model = corner_sheet(5, 5);
  ImplicitEuler integrator(model, implicit_settings(0.02), ForceOptions{});
  ClothState state = make_rest_state(model);
  ForceBuffers buffers;
  buffers.resize(model);
  std::vector<Vec3> force(model.particle_count());
  for (int step = 0; step < 10; ++step) {
    const double before = state.damping_work;
    ASSERT_EQ(integrator.step(state, 10.0).status, StepStatus::ok);
    const ForcePowers powers =
        evaluate_forces(model, state.position, state.velocity, kAllForceTerms, 1, buffers, force);
    EXPECT_EQ(state.damping_work, before + 0.02 * powers.damping);
    EXPECT_LE(powers.damping, 0.0);
  }
  EXPECT_LT(state.damping_work, 0.0);
}

TEST(ImplicitEuler, CountsConjugateGradientIterationsAndUnconvergedSolves) {
  const ClothModel model = corner_sheet(6, 6);
  IntegratorSettings settings = implicit_settings(1.0 / 60.0, 1e-12);
  settings.cg_max_iterations = 2;
  ImplicitEuler capped(model, settings, ForceOptions{});
  ClothState state = make_rest_state(model);
  for (int step = 0; step < 5; ++step) ASSERT_EQ(capped.step(state, 10.0).status, StepStatus::ok);
  EXPECT_EQ(capped.stats().cg_iterations, 10u);
  EXPECT_EQ(capped.stats().cg_max_iterations_in_a_step, 2u);
  EXPECT_EQ(capped.stats().cg_unconverged_solves, 5u);
  EXPECT_EQ(capped.stats().accepted_steps, 5u);
  // Two force evaluations per step (start and end), the start one reused from the previous end.
  EXPECT_EQ(capped.stats().force_evaluations, 6u);
}

TEST(ImplicitEuler, MatrixFollowsTheLatticeAdjacency) {
  const ClothModel model = corner_sheet(7, 7);
  ImplicitEuler integrator(model, implicit_settings(0.01), ForceOptions{});
  // Interior particle (3, 3): itself, 4 connector neighbours, 4 diagonal and 4 two away.
  const std::uint32_t centre = lattice_index(7, 3, 3);
  EXPECT_EQ(integrator.row_offset()[centre + 1] - integrator.row_offset()[centre], 13u);
  // A corner: itself, 2 neighbours, the diagonal one and 2 two away.
  EXPECT_EQ(integrator.row_offset()[1] - integrator.row_offset()[0], 6u);
}

TEST(ImplicitEuler, ResultsAreBitIdenticalForAnyThreadCount) {
  // 36 x 36 = 1296 particles: two reduction blocks, split differently by each thread count.
  LatticeDef def;
  def.rows = def.cols = 36;
  const ClothModel flat = build_lattice(def, Environment{}, {});
  AnchorPath moving;
  moving.kind = AnchorPathKind::sinusoid;
  moving.origin = flat.particle_rest_position[0];
  moving.amplitude = {0.0, 2.0, 0.0};
  moving.frequency = 0.7;
  const Anchor anchors[2] = {{0, moving}, {35, AnchorPath::fixed_at(flat.particle_rest_position[35])}};
  const ClothModel model = build_lattice(def, Environment{}, anchors);
  const auto run = [&](int threads) {
    ImplicitEuler integrator(model, implicit_settings(0.01, 1e-6), ForceOptions{kAllForceTerms, threads});
    ClothState state = make_rest_state(model);
    for (int step = 0; step < 8; ++step) EXPECT_EQ(integrator.step(state, 10.0).status, StepStatus::ok);
    return state;
  };
  const ClothState one = run(1);
  for (int threads : {2, 3}) {
    const ClothState many = run(threads);
    EXPECT_EQ(many.position, one.position) << threads << " threads";
    EXPECT_EQ(many.velocity, one.velocity) << threads << " threads";
    EXPECT_EQ(many.damping_work, one.damping_work) << threads << " threads";
  }
}

}  // namespace
}  // namespace clothsim

namespace clothsim {
namespace {

// The coarse-grid correction changes how fast CG converges, not what it converges to: on lattices
// whose sides are not multiples of the aggregate size (partial aggregates at the far edges), both
// preconditioners reach the same step; and at the default tolerance the two-level one needs far
// fewer iterations on cotton.
TEST(ImplicitEuler, AggregatesPreconditionerSolvesTheSameSystemInFewerIterations) {
  for (const int size : {13, 22}) {
    const SceneSpec spec = small_cotton(size);
    const ClothModel model = build_model(spec);
    const auto run = [&](bool two_level, double tolerance, ClothState& state) {
      IntegratorSettings settings = spec.integrator;
      settings.cg_tolerance = tolerance;
      settings.cg_max_iterations = 100000;
      settings.cg_two_level = two_level;
      settings.cg_multigrid = false;  // the 4 x 4 aggregates
      ImplicitEuler integrator(model, settings, ForceOptions{});
      for (int step = 0; step < 10; ++step) EXPECT_EQ(integrator.step(state, 10.0).status, StepStatus::ok);
      return integrator.stats().cg_iterations;
    };
    ClothState jacobi = build_initial_state(model, spec);
    ClothState two_level = jacobi;
    run(false, 1e-10, jacobi);
    run(true, 1e-10, two_level);
    EXPECT_LT(max_distance(jacobi.velocity, two_level.velocity), 1e-7) << "size " << size;
    EXPECT_LT(max_distance(jacobi.position, two_level.position), 1e-9) << "size " << size;

    ClothState unused_a = build_initial_state(model, spec);
    ClothState unused_b = unused_a;
    const std::uint64_t jacobi_iterations = run(false, spec.integrator.cg_tolerance, unused_a);
    const std::uint64_t two_level_iterations = run(true, spec.integrator.cg_tolerance, unused_b);
    // Jacobi's count grows with the lattice, the two-level one's does not (about 80 per step on
    // cotton from 16 x 16 to 128 x 128, docs/performance.md): at 22 x 22 the ratio is about 2.7.
    if (size >= 22) {
      EXPECT_LT(2 * two_level_iterations, jacobi_iterations) << "size " << size;
    }
    EXPECT_LT(two_level_iterations, jacobi_iterations) << "size " << size;
  }
}

}  // namespace
}  // namespace clothsim

namespace clothsim {
namespace {

// multigrid: the V-cycle in every solve; automatic: the default, the V-cycle where block Jacobi
// would take many iterations (IntegratorSettings::cg_vcycle_threshold).
enum class Preconditioner { jacobi, aggregates, multigrid, automatic };

IntegratorSettings with_preconditioner(IntegratorSettings settings, Preconditioner preconditioner) {
  settings.cg_two_level = preconditioner != Preconditioner::jacobi;
  settings.cg_multigrid = preconditioner == Preconditioner::multigrid || preconditioner == Preconditioner::automatic;
  settings.cg_vcycle_threshold =
      preconditioner == Preconditioner::multigrid ? 0.0 : IntegratorSettings{}.cg_vcycle_threshold;
  return settings;
}

// The multigrid V-cycle changes how fast CG converges, not what it converges to: on lattices with
// odd and even sides (a last fine node past the last coarse one) and one to three coarse levels,
// it reaches Jacobi's step at a tight tolerance; at the default one it needs fewer iterations
// than Jacobi and than the 4 x 4 aggregates.
TEST(ImplicitEuler, MultigridPreconditionerSolvesTheSameSystemInFewerIterations) {
  for (const int size : {13, 22, 33}) {
    const SceneSpec spec = small_cotton(size);
    const ClothModel model = build_model(spec);
    const auto run = [&](Preconditioner preconditioner, double tolerance, ClothState& state) {
      IntegratorSettings settings = with_preconditioner(spec.integrator, preconditioner);
      settings.cg_tolerance = tolerance;
      settings.cg_max_iterations = 100000;
      ImplicitEuler integrator(model, settings, ForceOptions{});
      for (int step = 0; step < 10; ++step) EXPECT_EQ(integrator.step(state, 10.0).status, StepStatus::ok);
      EXPECT_EQ(integrator.stats().cg_unconverged_solves, 0u);
      return integrator.stats().cg_iterations;
    };
    ClothState jacobi = build_initial_state(model, spec);
    ClothState multigrid = jacobi;
    run(Preconditioner::jacobi, 1e-10, jacobi);
    run(Preconditioner::multigrid, 1e-10, multigrid);
    EXPECT_LT(max_distance(jacobi.velocity, multigrid.velocity), 1e-7) << "size " << size;
    EXPECT_LT(max_distance(jacobi.position, multigrid.position), 1e-9) << "size " << size;

    const double tolerance = spec.integrator.cg_tolerance;
    std::uint64_t iterations[3];
    for (const Preconditioner preconditioner :
         {Preconditioner::jacobi, Preconditioner::aggregates, Preconditioner::multigrid}) {
      ClothState state = build_initial_state(model, spec);
      iterations[static_cast<int>(preconditioner)] = run(preconditioner, tolerance, state);
    }
    const std::uint64_t jacobi_iterations = iterations[0];
    const std::uint64_t aggregates_iterations = iterations[1];
    const std::uint64_t multigrid_iterations = iterations[2];
    EXPECT_LT(multigrid_iterations, aggregates_iterations) << "size " << size;
    EXPECT_LT(3 * multigrid_iterations, jacobi_iterations) << "size " << size;
  }
}

// The target: at most about 20 CG iterations per step on 128 x 128 cotton at the frame
// step (89 with the aggregates; docs/performance.md). Half a second of cotton-drape with the
// defaults, whose V-cycle solves lines on the fine level: 6.2 per step, at most 9 in one; with the
// point smoother instead, 12.4 and 15.
TEST(ImplicitEuler, MultigridTakesFewIterationsPerStepOn128By128Cotton) {
  const SceneSpec spec = builtin_scene("cotton-drape");
  ASSERT_EQ(spec.lattice.rows, 128);
  ASSERT_TRUE(spec.integrator.cg_two_level && spec.integrator.cg_multigrid &&
              spec.integrator.cg_line_smoother);  // the defaults
  const ClothModel model = build_model(spec);
  constexpr int kSteps = 30;
  const auto run = [&](bool lines) {
    IntegratorSettings settings = spec.integrator;
    settings.cg_line_smoother = lines;
    ImplicitEuler integrator(model, settings, ForceOptions{kAllForceTerms, 2});
    ClothState state = build_initial_state(model, spec);
    for (int step = 0; step < kSteps; ++step) EXPECT_EQ(integrator.step(state, 10.0).status, StepStatus::ok);
    EXPECT_EQ(integrator.stats().cg_unconverged_solves, 0u);
    return integrator.stats();
  };
  const IntegratorStats lines = run(true);
  EXPECT_LE(lines.cg_max_iterations_in_a_step, 12u);
  EXPECT_LE(lines.cg_iterations, 8u * kSteps);
  const IntegratorStats points = run(false);
  EXPECT_LE(points.cg_max_iterations_in_a_step, 25u);
  EXPECT_LE(points.cg_iterations, 20u * kSteps);
  EXPECT_GT(points.cg_iterations, 3 * lines.cg_iterations / 2);
}

// The V-cycle is set up only where the system is stiff relative to its mass
// (BlockSystem::kVCycleStiffness): at steps small enough for the mass to dominate, the default
// preconditioner is block Jacobi, the same bits as asking for it; at the frame step it is the
// V-cycle, in far fewer iterations than Jacobi.
TEST(ImplicitEuler, MassDominatedStepsSkipTheVCycle) {
  const SceneSpec spec = small_cotton(32);
  const ClothModel model = build_model(spec);
  const auto run = [&](Preconditioner preconditioner, double h) {
    IntegratorSettings settings = with_preconditioner(spec.integrator, preconditioner);
    settings.time_step = h;
    ImplicitEuler integrator(model, settings, ForceOptions{});
    ClothState state = build_initial_state(model, spec);
    for (int step = 0; step < 8; ++step) EXPECT_EQ(integrator.step(state, 10.0).status, StepStatus::ok);
    return std::pair{state, integrator.stats().cg_iterations};
  };
  const auto bytes = [](const std::vector<Vec3>& v) { return v.size() * sizeof(Vec3); };
  const auto [small_default, small_default_iterations] = run(Preconditioner::automatic, 2e-5);
  const auto [small_jacobi, small_jacobi_iterations] = run(Preconditioner::jacobi, 2e-5);
  EXPECT_EQ(small_default_iterations, small_jacobi_iterations);
  EXPECT_EQ(std::memcmp(small_default.position.data(), small_jacobi.position.data(), bytes(small_jacobi.position)), 0);
  EXPECT_EQ(std::memcmp(small_default.velocity.data(), small_jacobi.velocity.data(), bytes(small_jacobi.velocity)), 0);

  const auto [frame_default, frame_default_iterations] = run(Preconditioner::automatic, 1.0 / 60.0);
  const auto [frame_vcycle, frame_vcycle_iterations] = run(Preconditioner::multigrid, 1.0 / 60.0);
  const auto [frame_jacobi, frame_jacobi_iterations] = run(Preconditioner::jacobi, 1.0 / 60.0);
  EXPECT_EQ(frame_default_iterations, frame_vcycle_iterations);
  EXPECT_EQ(std::memcmp(frame_default.position.data(), frame_vcycle.position.data(), bytes(frame_vcycle.position)), 0);
  EXPECT_LT(3 * frame_default_iterations, frame_jacobi_iterations);
}

// The V-cycle's loops (Galerkin products, Gauss-Seidel bands, transfers) run in parallel on the
// levels with 1024 nodes or more: on 66 x 70 particles, levels 0 and 1. Bit for bit the same
// state for 1, 2 and 3 threads, with a moving anchor and even and odd sides.
TEST(ImplicitEuler, MultigridResultsAreBitIdenticalForAnyThreadCount) {
  SceneSpec spec = small_cotton(66);
  spec.lattice.cols = 70;
  parse_anchor_preset("edge-corners", spec.lattice, spec.anchors);
  spec.anchors[0].path.kind = AnchorPathKind::sinusoid;
  spec.anchors[0].path.amplitude = {0.0, 0.05, 0.0};
  spec.anchors[0].path.frequency = 2.0;
  const ClothModel model = build_model(spec);
  const auto run = [&](int threads) {
    ImplicitEuler integrator(model, spec.integrator, ForceOptions{kAllForceTerms, threads});
    ClothState state = build_initial_state(model, spec);
    for (int step = 0; step < 6; ++step) EXPECT_EQ(integrator.step(state, 10.0).status, StepStatus::ok);
    EXPECT_GT(integrator.stats().cg_iterations, 6u);
    return state;
  };
  const ClothState one = run(1);
  const auto bytes = [](const std::vector<Vec3>& v) { return v.size() * sizeof(Vec3); };
  for (int threads : {2, 3}) {
    const ClothState many = run(threads);
    ASSERT_EQ(many.position.size(), one.position.size());
    EXPECT_EQ(std::memcmp(many.position.data(), one.position.data(), bytes(one.position)), 0) << threads;
    EXPECT_EQ(std::memcmp(many.velocity.data(), one.velocity.data(), bytes(one.velocity)), 0) << threads;
    EXPECT_EQ(many.damping_work, one.damping_work) << threads << " threads";
  }
}

}  // namespace
}  // namespace clothsim
