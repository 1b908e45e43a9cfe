// The structured lattice kernel against the general element-list path: the same forces and
// damping power up to rounding on random configurations (stretched, bent, folded, flat with
// motion: the singular case, and one singular spring in a band of a bent sheet), on intact sheets
// and on torn and plastic ones, bit-for-bit thread
// independence of both paths, uniform sheets read without parameter arrays giving the same bits,
// collapsing connectors whose radial springs fade, the choice of the kernel by the recorded layout, edits followed
// through the model's revision, and the vectorisable arctangent against std::atan2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>

#include "forces/forces.h"
#include "forces/lattice_cases.h"
#include "forces/lattice_kernel.h"
#include "forces/vector_math.h"
#include "model/model_edits.h"
#include "model/spring_limits.h"
#include "test_support.h"

namespace clothsim {
namespace {

using testing::lattice;
using testing::randomise;
using testing::TestRandom;
using testing::torn_and_plastic;

struct Evaluation {
  std::vector<Vec3> force;
  ForcePowers powers;
};

Evaluation evaluate(const ClothModel& model, const std::vector<Vec3>& x, const std::vector<Vec3>& v, ForceKernel kernel,
                    int threads, ForceTerms terms = kAllForceTerms, Precision precision = Precision::float64) {
  ForceBuffers buffers;
  buffers.kernel = kernel;
  buffers.precision = precision;
  buffers.resize(model);
  EXPECT_EQ(buffers.uses_lattice_kernel(), kernel == ForceKernel::lattice);
  Evaluation out;
  out.force.resize(model.particle_count());
  out.powers = evaluate_forces(model, x, v, terms, threads, buffers, out.force);
  return out;
}

// Largest |f_lattice - f_general| relative to the largest force.
double relative_difference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double largest = 0.0;
  double difference = 0.0;
  for (std::size_t p = 0; p < a.size(); ++p) {
    largest = std::max(largest, norm(b[p]));
    difference = std::max(difference, norm(a[p] - b[p]));
  }
  return difference / largest;
}

void expect_paths_agree(const ClothModel& model, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                        ForceTerms terms = kAllForceTerms, double tolerance = 1e-13) {
  const Evaluation general = evaluate(model, x, v, ForceKernel::general, 1, terms);
  const Evaluation fast = evaluate(model, x, v, ForceKernel::lattice, 1, terms);
  EXPECT_LT(relative_difference(fast.force, general.force), tolerance)
      << model.rows << " x " << model.cols << ", terms " << terms;
  EXPECT_NEAR(fast.powers.damping, general.powers.damping, 1e-12 * std::abs(general.powers.damping) + 1e-300);
  EXPECT_EQ(fast.powers.drag, general.powers.drag);
}

TEST(LatticeKernel, AgreesWithTheGeneralPathOnRandomConfigurations) {
  int seed = 1;
  for (const auto& [rows, cols] :
       std::vector<std::pair<int, int>>{{1, 2}, {1, 5}, {2, 2}, {3, 1}, {4, 7}, {9, 6}, {17, 23}}) {
    const ClothModel model = lattice(rows, cols, 0.2);
    for (double amplitude : {0.05, 0.3, 0.9}) {  // gently to violently deformed (0.9 m folds it)
      std::vector<Vec3> x, v;
      randomise(model, amplitude, 2.0, static_cast<std::uint64_t>(seed++), x, v);
      expect_paths_agree(model, x, v);
    }
  }
}

TEST(LatticeKernel, AgreesWithTheGeneralPathForEachForceTerm) {
  const ClothModel model = lattice(6, 5, 0.3);
  std::vector<Vec3> x, v;
  randomise(model, 0.3, 1.0, 40, x, v);
  for (ForceTerms terms : {kGravity, kConnectorSprings, kAdjacentRadialSprings, kOppositeRadialSprings, kAirDrag,
                           kConnectorSprings | kSpringDamping, kAdjacentRadialSprings | kSpringDamping,
                           kOppositeRadialSprings | kSpringDamping, kAllForceTerms & ~kSpringDamping}) {
    const Evaluation general = evaluate(model, x, v, ForceKernel::general, 1, terms);
    const Evaluation fast = evaluate(model, x, v, ForceKernel::lattice, 1, terms);
    double largest = 0.0;
    for (const Vec3& f : general.force) largest = std::max(largest, norm(f));
    for (std::size_t p = 0; p < x.size(); ++p) {
      EXPECT_LE(norm(fast.force[p] - general.force[p]), 1e-13 * largest) << "terms " << terms << ", particle " << p;
    }
    EXPECT_NEAR(fast.powers.damping, general.powers.damping, 1e-12 * std::abs(general.powers.damping));
  }
}

// A flat sheet is singular for every opposite spring (exactly straight): the bending plane comes
// from the relative velocities, in both paths alike. Moving only out of the plane, only in it,
// and not at all.
TEST(LatticeKernel, AgreesWithTheGeneralPathOnAFlatSheetInMotion) {
  const ClothModel model = lattice(8, 7);
  TestRandom random(41);
  for (const Vec3 mask : {Vec3{0, 1, 0}, Vec3{1, 0, 1}, Vec3{1, 1, 1}, Vec3{0, 0, 0}}) {
    std::vector<Vec3> v(model.particle_count());
    for (Vec3& vi : v) {
      const Vec3 r = random.vector(-1, 1);
      vi = {r.x * mask.x, r.y * mask.y, r.z * mask.z};
    }
    expect_paths_agree(model, model.particle_rest_position, v);
  }
  // A folded row: particle 1 of a 1 x 3 strip placed back onto particle 0's side makes the
  // opposite spring's connectors parallel (theta = 0).
  const ClothModel strip = lattice(1, 3);
  std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {0.5, 0, 0}};
  std::vector<Vec3> v = {{0, 0, 0}, {0, 0.3, 0}, {0, -0.2, 0.1}};
  expect_paths_agree(strip, x, v);
}

// The kernel takes a band of rows (at least 256 particles: 32 rows of 8 here) spring by spring
// where one of its springs is singular; it finds a straight spring in the band's first row before
// computing anything, any other singular spring in the springs' own test. Each way, on a bent and
// moving sheet: a straight opposite spring in the first row of the first band, one in a later row
// of it (found by the springs' test), an adjacent spring folded flat in the second band (its
// south arm laid along its east arm), and all three, one band at a time and together.
TEST(LatticeKernel, AgreesWithTheGeneralPathWhereABandHasOneSingularSpring) {
  const ClothModel model = lattice(40, 8, 0.2);
  const std::size_t cols = 8;
  const auto straighten = [&](std::vector<Vec3>& x, std::size_t p) { x[p] = 0.5 * (x[p - 1] + x[p + 1]); };
  const auto fold = [&](std::vector<Vec3>& x, std::size_t p) { x[p + cols] = x[p] + 0.5 * (x[p + 1] - x[p]); };
  for (int pattern = 1; pattern < 8; ++pattern) {
    std::vector<Vec3> x, v;
    randomise(model, 0.3, 2.0, static_cast<std::uint64_t>(90 + pattern), x, v);
    if ((pattern & 1) != 0) straighten(x, 3);              // row 0, column 3
    if ((pattern & 2) != 0) straighten(x, 17 * cols + 5);  // row 17, column 5
    if ((pattern & 4) != 0) fold(x, 35 * cols + 2);        // row 35, column 2: the (E, S) spring at 0 degrees
    SCOPED_TRACE("pattern " + std::to_string(pattern));
    expect_paths_agree(model, x, v);
    const Evaluation one = evaluate(model, x, v, ForceKernel::lattice, 1);
    const Evaluation two = evaluate(model, x, v, ForceKernel::lattice, 2);
    EXPECT_EQ(std::memcmp(one.force.data(), two.force.data(), one.force.size() * sizeof(Vec3)), 0);
  }
}

// A strip moving along its own line: every opposite spring straight and no transverse motion, so
// no bending plane. The kernel's unit vectors (e times 1/l) are not exactly +-1 where the general
// path's (e / l) are; the rounding left in the turning rates must not pick a plane (it once did,
// and the damping of the straight springs then pushed along the strip).
TEST(LatticeKernel, AgreesWithTheGeneralPathOnAStripMovingAlongItsLine) {
  const ClothModel strip = lattice(1, 5);
  const std::vector<Vec3> x = {{-2, 0, 0},
                               {-1.006807798466935, 0, 0},
                               {-0.0096464390858170164, 0, 0},
                               {0.99047308355091668, 0, 0},
                               {2.92, 0, 0}};
  const std::vector<Vec3> v = {
      {0, 0, 0}, {-0.2083870101907717, 0, 0}, {-0.4033382470181983, 0, 0}, {-0.5297294810059696, 0, 0}, {1, 0, 0}};
  expect_paths_agree(strip, x, v);
}

// Gravity is mass times g in both paths, with a mass other than 1 (the paper's 1 kg would hide a
// forgotten mass) set as the viewer sets it. (The general path is what torn and irregular models
// take; a lattice model takes the kernel unless asked, so it is asked here.)
// Connectors collapsed to 2 % to 45 % of their length, so that the radial springs on them fade
// (forces/element_math.inc): the kernel's fade (computed per connector, lattice_spring::arm_fade)
// agrees with the element's, on intact sheets and on torn and plastic ones (whose connectors'
// rest lengths differ from the original lengths the fade is measured against).
TEST(LatticeKernel, AgreesWithTheGeneralPathWhereRadialSpringsFade) {
  std::uint64_t seed = 70;
  for (const auto& [rows, cols] : std::vector<std::pair<int, int>>{{2, 3}, {5, 4}, {9, 8}}) {
    for (double broken : {-1.0, 0.0, 0.2}) {  // -1: the intact, uniform sheet
      const ClothModel model = broken < 0.0 ? lattice(rows, cols, 0.2) : torn_and_plastic(rows, cols, broken, seed++);
      std::vector<Vec3> x, v;
      randomise(model, 0.05, 2.0, seed++, x, v);
      ASSERT_GT(testing::collapse_connectors(model, x, seed++), 0);
      SCOPED_TRACE(std::to_string(rows) + " x " + std::to_string(cols) + ", broken " + std::to_string(broken));
      expect_paths_agree(model, x, v);
      expect_paths_agree(model, x, v, kAdjacentRadialSprings | kOppositeRadialSprings);
    }
  }
}

// The kernel leaves the fade out of bands of particles with no arm inside it. One connector
// collapsed across the boundary of two bands (the radial pass runs over bands of at least 256
// particles, whole rows: rows 0-15 and 16-19 of a 20 x 16 sheet): the south arm of a particle of
// the first band and the north arm of one of the second, which must fade in both.
TEST(LatticeKernel, AgreesWithTheGeneralPathWhereOneConnectorFadesAcrossBands) {
  const ClothModel model = lattice(20, 16, 0.2);
  std::vector<Vec3> x, v;
  randomise(model, 0.05, 2.0, 75, x, v);
  const std::size_t above = 15 * 16 + 5;  // row 15, col 5
  const std::size_t below = above + 16;   // row 16, col 5
  x[below] = x[above] + 0.2 * (x[below] - x[above]);
  expect_paths_agree(model, x, v);
}

TEST(LatticeKernel, GravityAloneIsMassTimesG) {
  ClothModel model = lattice(4, 5);
  set_particle_mass(model, 2.5);
  const std::vector<Vec3> v(model.particle_count());
  for (ForceKernel kernel : {ForceKernel::general, ForceKernel::lattice}) {
    SCOPED_TRACE(kernel == ForceKernel::general ? "general" : "lattice");
    for (const Vec3& f : evaluate(model, model.particle_rest_position, v, kernel, 1, kGravity).force) {
      EXPECT_DOUBLE_EQ(f.y, -9.81 * 2.5);
      EXPECT_EQ(f.x, 0.0);
      EXPECT_EQ(f.z, 0.0);
    }
  }
}

TEST(LatticeKernel, FlatSheetAtRestWithoutGravityHasExactlyZeroForce) {
  LatticeDef def;
  def.rows = 5;
  def.cols = 6;
  const ClothModel model = build_lattice(def, Environment{{0, 0, 0}, 0.0}, {});
  const std::vector<Vec3> v(model.particle_count());
  for (const Vec3& f : evaluate(model, model.particle_rest_position, v, ForceKernel::lattice, 1).force) {
    EXPECT_EQ(f, Vec3{});
  }
}

TEST(LatticeKernel, CoincidentParticlesGiveFiniteForces) {
  const ClothModel model = lattice(3, 3);
  std::vector<Vec3> x = model.particle_rest_position;
  x[4] = x[5];  // centre on its east neighbour: a zero-length connector, degenerate radial springs
  const std::vector<Vec3> v(model.particle_count());
  expect_paths_agree(model, x, v);
  for (const Vec3& f : evaluate(model, x, v, ForceKernel::lattice, 1).force) EXPECT_TRUE(is_finite(f));
}

TEST(LatticeKernel, BothPathsAreBitIdenticalForAnyThreadCount) {
  const ClothModel model = lattice(41, 37, 0.1);
  std::vector<Vec3> x, v;
  randomise(model, 0.3, 1.0, 42, x, v);
  for (ForceKernel kernel : {ForceKernel::general, ForceKernel::lattice}) {
    const Evaluation one = evaluate(model, x, v, kernel, 1);
    for (int threads : {2, 3, 4}) {
      const Evaluation many = evaluate(model, x, v, kernel, threads);
      EXPECT_EQ(std::memcmp(one.force.data(), many.force.data(), one.force.size() * sizeof(Vec3)), 0)
          << threads << " threads";
      EXPECT_EQ(one.powers.damping, many.powers.damping) << threads << " threads";
    }
  }
}

// An intact sheet whose springs have their family's values is read from one value per family,
// without the 26 parameter arrays; the same sheet read from the arrays (held because a limit can
// change it) gives the same bits, in the singular branch too and with terms switched off.
TEST(LatticeKernel, UniformSheetsNeedNoParameterArraysAndGiveTheSameBits) {
  const ClothModel uniform = lattice(23, 19, 0.1);
  ClothModel limited = uniform;
  SpringLimits limits;
  limits.break_strain = 0.5;
  apply_spring_limits(limited, limits);
  ForceBuffers uniform_buffers;
  uniform_buffers.resize(uniform);
  ForceBuffers array_buffers;
  array_buffers.resize(limited);
  ASSERT_TRUE(uniform_buffers.uses_lattice_kernel() && array_buffers.uses_lattice_kernel());
  EXPECT_TRUE(uniform_buffers.lattice.uniform());
  EXPECT_FALSE(array_buffers.lattice.uniform());
  const LatticeCounts counts = lattice_counts(23, 19);
  EXPECT_EQ(uniform_buffers.bytes(), ForceBuffers::bytes_for(counts, ForceKernel::automatic, false));
  EXPECT_EQ(array_buffers.bytes(), ForceBuffers::bytes_for(counts, ForceKernel::automatic, true));
  EXPECT_LT(uniform_buffers.bytes(), array_buffers.bytes() * 6 / 10);

  std::uint64_t seed = 70;
  for (double amplitude : {0.0, 0.3}) {  // 0: flat and moving, the singular branch
    std::vector<Vec3> x, v;
    randomise(uniform, amplitude, 1.0, seed++, x, v);
    for (ForceTerms terms : {kAllForceTerms, kAllForceTerms & ~kSpringDamping, kOppositeRadialSprings | kGravity}) {
      for (int threads : {1, 3}) {
        std::vector<Vec3> from_values(uniform.particle_count());
        std::vector<Vec3> from_arrays(uniform.particle_count());
        const ForcePowers a = evaluate_forces(uniform, x, v, terms, threads, uniform_buffers, from_values);
        const ForcePowers b = evaluate_forces(limited, x, v, terms, threads, array_buffers, from_arrays);
        EXPECT_EQ(std::memcmp(from_values.data(), from_arrays.data(), from_values.size() * sizeof(Vec3)), 0)
            << "amplitude " << amplitude << ", terms " << terms << ", " << threads << " threads";
        EXPECT_EQ(a.damping, b.damping);
      }
    }
  }
}

TEST(LatticeKernel, AgreesWithTheGeneralPathOnTornAndPlasticSheets) {
  std::uint64_t seed = 100;
  for (const auto& [rows, cols] : std::vector<std::pair<int, int>>{{1, 5}, {3, 3}, {9, 6}, {17, 23}}) {
    for (double broken : {0.0, 0.1, 0.5}) {
      const ClothModel model = torn_and_plastic(rows, cols, broken, seed++);
      for (double amplitude : {0.05, 0.3, 0.9}) {
        std::vector<Vec3> x, v;
        randomise(model, amplitude, 2.0, seed++, x, v);
        expect_paths_agree(model, x, v, kAllForceTerms, 1e-12);
      }
      // Flat and moving: every straight spring takes the singular branch.
      std::vector<Vec3> x, v;
      randomise(model, 0.0, 1.0, seed++, x, v);
      expect_paths_agree(model, x, v, kAllForceTerms, 1e-12);
    }
  }
}

// In float32 forces too (tests/forces/test_float32_forces.cpp): every particle's float
// operations are the same whichever thread computes them.
TEST(LatticeKernel, TornAndPlasticSheetsAreBitIdenticalForAnyThreadCount) {
  const ClothModel model = torn_and_plastic(41, 37, 0.1, 7);
  std::vector<Vec3> x, v;
  randomise(model, 0.3, 1.0, 43, x, v);
  for (Precision precision : {Precision::float64, Precision::float32}) {
    const Evaluation one = evaluate(model, x, v, ForceKernel::lattice, 1, kAllForceTerms, precision);
    for (int threads : {2, 3, 4}) {
      const Evaluation many = evaluate(model, x, v, ForceKernel::lattice, threads, kAllForceTerms, precision);
      EXPECT_EQ(std::memcmp(one.force.data(), many.force.data(), one.force.size() * sizeof(Vec3)), 0)
          << threads << " threads, " << to_string(precision);
      EXPECT_EQ(one.powers.damping, many.powers.damping) << threads << " threads, " << to_string(precision);
    }
  }
}

// The kernel is chosen by the layout build_lattice records, not by looking for uniform values:
// torn, plastic and varied sheets stay on it; a model whose springs no longer match its layout,
// or one built in another order, takes the general path.
TEST(LatticeKernel, IsChosenByTheRecordedLayout) {
  const auto uses_kernel = [](const ClothModel& model) {
    ForceBuffers buffers;
    buffers.resize(model);
    return buffers.uses_lattice_kernel();
  };
  EXPECT_TRUE(uses_kernel(lattice(5, 4)));
  EXPECT_TRUE(uses_kernel(torn_and_plastic(5, 4, 0.3, 9)));

  ClothModel general = lattice(5, 4);
  general.layout = ModelLayout::general;
  EXPECT_FALSE(uses_kernel(general));

  ClothModel mismatched = lattice(5, 4);  // a radial spring moved by hand to a particle's diagonal
  mismatched.radial_particles[0][1] = mismatched.radial_particles[0][0] + 5 + 1;
  EXPECT_FALSE(uses_kernel(mismatched));
}

// An edit between evaluations moves the model's revision; the kernel copies the parameters again
// without being prepared again.
TEST(LatticeKernel, FollowsModelEditsThroughTheRevision) {
  ClothModel model = lattice(6, 5, 0.1);
  std::vector<Vec3> x, v;
  randomise(model, 0.3, 1.0, 44, x, v);
  ForceBuffers buffers;
  buffers.resize(model);
  std::vector<Vec3> force(model.particle_count());
  evaluate_forces(model, x, v, kAllForceTerms, 1, buffers, force);
  break_connector(model, 7);
  set_connector_rest_length(model, 3, 1.2);
  set_radial_rest_angle(model, 11, 2.0);
  set_spring_family(model, SpringFamily::opposite, {900.0, 100.0});
  const ForcePowers powers = evaluate_forces(model, x, v, kAllForceTerms, 1, buffers, force);
  EXPECT_TRUE(buffers.uses_lattice_kernel());
  const Evaluation general = evaluate(model, x, v, ForceKernel::general, 1);
  EXPECT_LT(relative_difference(force, general.force), 1e-13);
  EXPECT_NEAR(powers.damping, general.powers.damping, 1e-12 * std::abs(general.powers.damping));
}

// Distance in units in the last place between two finite doubles of the same sign.
double ulps(double a, double b) {
  if (a == b) return 0.0;
  return std::abs(a - b) / (std::nextafter(std::abs(b), std::numeric_limits<double>::infinity()) - std::abs(b));
}

TEST(VectorMath, Atan2FirstQuadrantIsWithinTwoUlpsOfLibm) {
  TestRandom random(43);
  double worst = 0.0;
  for (int i = 0; i < 200000; ++i) {
    // Ratios over many orders of magnitude, both orders of y and x.
    const double y = std::pow(10.0, random.uniform(-14, 3));
    const double x = std::pow(10.0, random.uniform(-14, 3));
    worst = std::max(worst, ulps(vector_math::atan2_first_quadrant(y, x), std::atan2(y, x)));
    const double a = random.uniform(0, 1);  // near the interval boundaries 0.66, tan(pi/8), 1
    worst = std::max(worst, ulps(vector_math::atan2_first_quadrant(a, 1.0), std::atan2(a, 1.0)));
    worst = std::max(worst, ulps(vector_math::atan2_first_quadrant(1.0, a), std::atan2(1.0, a)));
  }
  EXPECT_LE(worst, 2.0);
  // Exact values at the ends and the diagonal.
  EXPECT_EQ(vector_math::atan2_first_quadrant(0.0, 1.0), 0.0);
  EXPECT_EQ(vector_math::atan2_first_quadrant(1.0, 0.0), std::numbers::pi / 2);
  EXPECT_EQ(vector_math::atan2_first_quadrant(2.0, 2.0), std::numbers::pi / 4);
  EXPECT_EQ(vector_math::atan2_first_quadrant(1e-300, 1.0), 1e-300);
}

}  // namespace
}  // namespace clothsim
