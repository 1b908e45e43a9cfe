// The structured lattice kernel against the general element-list path: the same forces and
// damping power up to rounding on random configurations (stretched, bent, folded, flat with
// motion: the singular case), bit-for-bit thread independence of both paths, detection of
// intact lattices, and the vectorisable arctangent against std::atan2.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

#include "forces/forces.h"
#include "forces/lattice_kernel.h"
#include "forces/vector_math.h"
#include "test_support.h"

namespace clothsim {
namespace {

using testing::TestRandom;

ClothModel lattice(int rows, int cols, double drag = 0.0) {
  LatticeDef def;  // the paper's material
  def.rows = rows;
  def.cols = cols;
  return build_lattice(def, Environment{{0.0, -9.81, 0.0}, drag}, {});
}

struct Evaluation {
  std::vector<Vec3> force;
  ForcePowers powers;
};

Evaluation evaluate(const ClothModel& model, const std::vector<Vec3>& x, const std::vector<Vec3>& v, ForceKernel kernel,
                    int threads, ForceTerms terms = kAllForceTerms) {
  ForceBuffers buffers;
  buffers.kernel = kernel;
  buffers.resize(model);
  EXPECT_EQ(buffers.uses_lattice_kernel(), kernel == ForceKernel::lattice);
  Evaluation out;
  out.force.resize(model.particle_count());
  out.powers = evaluate_forces(model, x, v, terms, threads, buffers, out.force);
  return out;
}

// Random positions around the rest lattice (amplitude in m) and random velocities.
void randomise(const ClothModel& model, double amplitude, double speed, std::uint64_t seed, std::vector<Vec3>& x,
               std::vector<Vec3>& v) {
  TestRandom random(seed);
  x = model.particle_rest_position;
  v.assign(model.particle_count(), Vec3{});
  for (std::size_t p = 0; p < x.size(); ++p) {
    x[p] += random.vector(-amplitude, amplitude);
    v[p] = random.vector(-speed, speed);
  }
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
                        ForceTerms terms = kAllForceTerms) {
  const Evaluation general = evaluate(model, x, v, ForceKernel::general, 1, terms);
  const Evaluation fast = evaluate(model, x, v, ForceKernel::lattice, 1, terms);
  EXPECT_LT(relative_difference(fast.force, general.force), 1e-13)
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

TEST(LatticeKernel, DetectsOnlyIntactUniformLattices) {
  const ClothModel intact = lattice(5, 4);
  const std::optional<LatticeMaterial> material = detect_lattice(intact);
  ASSERT_TRUE(material.has_value());
  EXPECT_EQ(material->opposite_stiffness, 1400.0);
  EXPECT_EQ(material->adjacent_rest_angle, std::numbers::pi / 2);

  ClothModel softer = intact;  // one connector of a different material
  softer.connector_stiffness[7] *= 0.5;
  EXPECT_FALSE(detect_lattice(softer).has_value());

  ClothModel torn = intact;  // a connector removed (the radial springs still name it)
  torn.connector_particles.pop_back();
  EXPECT_FALSE(detect_lattice(torn).has_value());

  ClothModel reordered = intact;
  std::swap(reordered.radial_particles[0], reordered.radial_particles[1]);
  EXPECT_FALSE(detect_lattice(reordered).has_value());

  // ForceKernel::automatic falls back to the general path for the modified models.
  ForceBuffers buffers;
  buffers.resize(softer);
  EXPECT_FALSE(buffers.uses_lattice_kernel());
  buffers.resize(intact);
  EXPECT_TRUE(buffers.uses_lattice_kernel());
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
