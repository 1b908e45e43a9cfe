// The lattice kernel's float32 forces (forces/lattice_kernel.h, "Precision") against its float64
// ones: on random states of intact, torn and plastic sheets, on states the paper's scenes pass
// through, and on straight and folded radial springs (the singular configurations), where they
// stay finite; half the scratch; and the float32 arctangent against libm. (The same bits for any
// thread count: test_lattice_kernel.cpp, TornAndPlasticSheetsAreBitIdenticalForAnyThreadCount.)
//
// The bound. Each spring's float32 force carries a few float ulps (eps_f = 6e-8) of its own size,
// and a particle's force is a sum of some twenty of them, gravity and drag added in double. Net
// forces can be much smaller than their terms, so the error is measured against the largest force
// on any particle of the sheet: kRelativeBound = 2e-5 of it (about 170 eps_f; the largest
// measured is in each test's comment). The damping power, a sum of squares, within 1e-4 of itself.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "forces/forces.h"
#include "forces/lattice_cases.h"
#include "forces/vector_math.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene_simulation.h"

namespace clothsim {
namespace {

using testing::lattice;
using testing::randomise;
using testing::TestRandom;
using testing::torn_and_plastic;

constexpr double kRelativeBound = 2e-5;

struct Evaluation {
  std::vector<Vec3> force;
  ForcePowers powers;
};

Evaluation evaluate(const ClothModel& model, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                    Precision precision, int threads = 1) {
  ForceBuffers buffers;
  buffers.kernel = ForceKernel::lattice;
  buffers.precision = precision;
  buffers.resize(model);
  EXPECT_EQ(buffers.lattice.precision(), precision);
  Evaluation out;
  out.force.resize(model.particle_count());
  out.powers = evaluate_forces(model, x, v, kAllForceTerms, threads, buffers, out.force);
  return out;
}

bool all_finite(const std::vector<Vec3>& force) {
  for (const Vec3& f : force) {
    if (!is_finite(f)) return false;
  }
  return true;
}

// max |f32 - f64| / max |f64|; with `same_branch` (both precisions see the configuration alike),
// also that relative difference below kRelativeBound and the damping powers within 1e-4. The
// float32 forces are always checked finite.
double compare(const ClothModel& model, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
               bool same_branch = true) {
  const Evaluation f64 = evaluate(model, x, v, Precision::float64);
  const Evaluation f32 = evaluate(model, x, v, Precision::float32);
  EXPECT_TRUE(all_finite(f32.force) && std::isfinite(f32.powers.damping));
  double largest = 0.0;
  double difference = 0.0;
  for (std::size_t p = 0; p < f64.force.size(); ++p) {
    largest = std::max(largest, norm(f64.force[p]));
    difference = std::max(difference, norm(f32.force[p] - f64.force[p]));
  }
  const double relative = largest > 0.0 ? difference / largest : difference;
  if (same_branch) {
    EXPECT_LT(relative, kRelativeBound);
    EXPECT_NEAR(f32.powers.damping, f64.powers.damping, 1e-4 * std::abs(f64.powers.damping) + 1e-30);
  }
  EXPECT_EQ(f32.powers.drag, f64.powers.drag);  // from the float64 velocities, in double
  return relative;
}

// Random states, gently to violently deformed (0.9 m folds the sheet), with speeds of 2 m/s, of
// intact sheets and of torn and plastic ones (10 % and 50 % of connectors broken, every spring's
// values different). Largest measured: 4.3e-6.
TEST(Float32Forces, AgreeWithFloat64OnRandomIntactTornAndPlasticSheets) {
  std::uint64_t seed = 1;
  double worst = 0.0;
  for (const auto& [rows, cols] : std::vector<std::pair<int, int>>{{1, 5}, {3, 3}, {9, 6}, {17, 23}}) {
    for (double broken : {-1.0, 0.0, 0.1, 0.5}) {  // -1: the intact, uniform sheet
      const ClothModel model = broken < 0.0 ? lattice(rows, cols, 0.2) : torn_and_plastic(rows, cols, broken, seed++);
      for (double amplitude : {0.05, 0.3, 0.9}) {
        std::vector<Vec3> x, v;
        randomise(model, amplitude, 2.0, seed++, x, v);
        SCOPED_TRACE(std::to_string(rows) + " x " + std::to_string(cols) + ", broken " + std::to_string(broken) +
                     ", amplitude " + std::to_string(amplitude));
        worst = std::max(worst, compare(model, x, v));
      }
    }
  }
  std::printf("largest relative difference %.3g\n", worst);
}

// Collapsed connectors whose radial springs fade (forces/element_math.inc): the float32 kernel's
// fade agrees with the float64 one's, on intact and on torn and plastic sheets.
TEST(Float32Forces, AgreeWithFloat64WhereRadialSpringsFade) {
  std::uint64_t seed = 90;
  double worst = 0.0;
  for (double broken : {-1.0, 0.0, 0.2}) {
    const ClothModel model = broken < 0.0 ? lattice(9, 8, 0.2) : torn_and_plastic(9, 8, broken, seed++);
    std::vector<Vec3> x, v;
    randomise(model, 0.05, 2.0, seed++, x, v);
    ASSERT_GT(testing::collapse_connectors(model, x, seed++), 0);
    SCOPED_TRACE("broken " + std::to_string(broken));
    worst = std::max(worst, compare(model, x, v));
  }
  std::printf("largest relative difference %.3g\n", worst);
}

// The states the paper's scenes pass through (run in float64 to 0.5 s): a sheet hanging from its
// centre (paper-fig5, paper-fig6) and from two corners (drape-corners), nearly straight opposite
// springs everywhere. Largest measured: 2.0e-6 (drape-corners).
TEST(Float32Forces, AgreeWithFloat64OnThePaperScenesStates) {
  for (const char* name : {"paper-fig5", "paper-fig6", "drape-corners"}) {
    SceneSpec spec = builtin_scene(name);
    Simulation simulation = testing::one_thread_simulation(spec);
    for (int frame = 1; frame <= 30; ++frame) ASSERT_TRUE(simulation.advance_to(frame / 60.0)) << name;
    SCOPED_TRACE(name);
    const double relative = compare(simulation.model(), simulation.state().position, simulation.state().velocity);
    std::printf("%s: relative difference %.3g\n", name, relative);
  }
}

// Straight and folded radial springs, the singular configurations, in float: a flat sheet at rest
// and in motion (every opposite spring exactly straight; the bending plane from the motion), a
// strip folded exactly back on itself (an opposite spring at 0 degrees), a corner folded onto its
// neighbour (adjacent springs near 0 degrees), and strips straight to within 1e-8 to 1e-5 m.
// Every force is finite. Where both precisions see the same configuration (exactly singular, or
// bent well above float's rounding) they agree within the bound. A spring bent by less than
// SingularLimits<float>::sine = 1e-6 (forces/lattice_spring.h) but more than float64's 1e-12 is
// taken from the motion in float32 and from the geometry in float64: two one-sided limits of a
// force whose direction the positions no longer fix in float (a cone point of the energy, or the
// damping of a straight spring), so there only finiteness is asserted.
TEST(Float32Forces, StraightAndFoldedRadialSpringsStayFinite) {
  // Flat, at rest and moving.
  {
    const ClothModel model = lattice(7, 8, 0.2);
    std::vector<Vec3> x, v;
    randomise(model, 0.0, 0.0, 3, x, v);
    compare(model, x, v);
    randomise(model, 0.0, 1.0, 4, x, v);
    compare(model, x, v);
  }
  // A 1 x 3 strip folded in half: particle 2 back on particle 0, at rest and opening.
  {
    const ClothModel model = lattice(1, 3);
    std::vector<Vec3> x = {{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
    for (const Vec3& speed : {Vec3{}, Vec3{0.0, 0.0, 0.3}}) {
      std::vector<Vec3> v = {Vec3{}, Vec3{}, speed};
      compare(model, x, v);
    }
  }
  // A 2 x 2 sheet with its corner 3 folded onto 1: the adjacent springs at 1 close to 0 degrees.
  {
    const ClothModel model = lattice(2, 2);
    std::vector<Vec3> x = model.particle_rest_position;
    x[3] = x[1] + Vec3{-1e-7, 0.0, 1e-7};
    std::vector<Vec3> v(4, Vec3{0.0, 0.1, 0.0});
    v[2] = {0.0, 0.0, 0.5};
    compare(model, x, v);
  }
  // Straight to within rounding: transverse offsets of 1e-8 to 1e-4 m on a 1 x 9 strip, moving
  // across the bend.
  for (double offset : {1e-8, 1e-7, 1e-6, 1e-5, 1e-4}) {
    const ClothModel model = lattice(1, 9);
    std::vector<Vec3> x = model.particle_rest_position;
    std::vector<Vec3> v(9, Vec3{});
    for (std::size_t p = 0; p < x.size(); ++p) {
      x[p].y += offset * ((p % 2 == 0) ? 1.0 : -1.0);
      v[p].z = 0.2 * std::sin(static_cast<double>(p));
    }
    SCOPED_TRACE(offset);
    compare(model, x, v, offset >= 1e-5);
  }
}

// float32 scratch is half the float64's (the memory estimate counts it from bytes_for).
TEST(Float32Forces, HoldHalfTheScratch) {
  const ClothModel model = lattice(31, 29);
  ForceBuffers f64;
  f64.resize(model);
  ForceBuffers f32;
  f32.precision = Precision::float32;
  f32.resize(model);
  const LatticeCounts counts = lattice_counts(31, 29);
  EXPECT_EQ(f32.bytes(), ForceBuffers::bytes_for(counts, ForceKernel::automatic, false, Precision::float32));
  EXPECT_LT(f32.bytes(), f64.bytes() * 6 / 10);
}

// The float version of the vectorisable arctangent: within 2 float ulps of libm's atanf2 over the
// whole first quadrant, exact on the axes and the diagonal.
TEST(Float32Forces, Atan2FirstQuadrantIsWithinTwoFloatUlpsOfLibm) {
  TestRandom random(5);
  float worst = 0.0f;
  for (int i = 0; i < 200000; ++i) {
    const auto y = static_cast<float>(std::pow(10.0, random.uniform(-30.0, 10.0)));
    const auto x = static_cast<float>(std::pow(10.0, random.uniform(-30.0, 10.0)));
    const float exact = std::atan2(y, x);
    const float error = std::abs(vector_math::atan2_first_quadrant(y, x) - exact);
    worst = std::max(worst, error / (std::nextafter(exact, 10.0f) - exact));
  }
  std::printf("largest error %.2f ulps\n", static_cast<double>(worst));
  EXPECT_LE(worst, 2.0f);
  EXPECT_EQ(vector_math::atan2_first_quadrant(0.0f, 1.0f), 0.0f);
  EXPECT_EQ(vector_math::atan2_first_quadrant(1.0f, 0.0f), std::numbers::pi_v<float> / 2);
  EXPECT_EQ(vector_math::atan2_first_quadrant(2.0f, 2.0f), std::numbers::pi_v<float> / 4);
}

}  // namespace
}  // namespace clothsim
