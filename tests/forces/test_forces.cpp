// The assembled force function on whole lattices: equilibrium of the flat sheet, Newton's third
// law, the gradient of the total potential energy, the damping power, and independence of the
// thread count.
#include "forces/forces.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <numbers>

#include "model/cloth_model.h"
#include "test_support.h"

namespace clothsim {
namespace {

using testing::TestRandom;

ClothModel paper_lattice(int rows, int cols, Vec3 gravity = {0, -9.81, 0}, double drag = 0.0) {
  LatticeDef lattice;  // the paper's material: 1 kg, (4, 1), (1400, 200), (80, 5), L = 1
  lattice.rows = rows;
  lattice.cols = cols;
  return build_lattice(lattice, Environment{gravity, drag}, {});
}

std::vector<Vec3> perturbed(const ClothModel& model, double amplitude, std::uint64_t seed) {
  TestRandom random(seed);
  std::vector<Vec3> x = model.particle_rest_position;
  for (Vec3& p : x) p += random.vector(-amplitude, amplitude);
  return x;
}

std::vector<Vec3> evaluate(const ClothModel& model, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                           ForceTerms terms, int threads, ForcePowers* powers = nullptr) {
  ForceBuffers buffers;
  buffers.resize(model);
  std::vector<Vec3> f(model.particle_count());
  const ForcePowers p = evaluate_forces(model, x, v, terms, threads, buffers, f);
  if (powers != nullptr) *powers = p;
  return f;
}

double potential_energy(const ClothModel& model, const std::vector<Vec3>& x) {
  ClothState state;
  state.position = x;
  state.velocity.assign(x.size(), Vec3{});
  return compute_energy(model, state).total();
}

TEST(Forces, FlatSheetWithoutGravityIsInEquilibrium) {
  const ClothModel model = paper_lattice(7, 5, {0, 0, 0});
  const std::vector<Vec3> v(model.particle_count());
  for (const Vec3& f : evaluate(model, model.particle_rest_position, v, kAllForceTerms, 1)) {
    EXPECT_EQ(f, Vec3{});
  }
}

TEST(Forces, GravityAloneIsMassTimesG) {
  // Masses other than 1, and different per particle: a force that forgot the mass would pass
  // with the paper's 1 kg.
  ClothModel model = paper_lattice(3, 4);
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    model.particle_mass[p] = 0.5 + 0.25 * static_cast<double>(p);
    model.particle_inverse_mass[p] = 1.0 / model.particle_mass[p];
  }
  const std::vector<Vec3> v(model.particle_count());
  const std::vector<Vec3> f = evaluate(model, perturbed(model, 0.3, 1), v, kGravity, 1);
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    EXPECT_DOUBLE_EQ(f[p].y, -9.81 * model.particle_mass[p]) << "particle " << p;
    EXPECT_EQ(f[p].x, 0.0);
    EXPECT_EQ(f[p].z, 0.0);
  }
}

TEST(Forces, InternalForcesSumToZero) {
  const ClothModel model = paper_lattice(6, 6, {0, 0, 0});
  TestRandom random(2);
  std::vector<Vec3> v(model.particle_count());
  for (Vec3& vi : v) vi = random.vector(-1, 1);
  Vec3 total;
  Vec3 largest;
  for (const Vec3& f : evaluate(model, perturbed(model, 0.4, 3), v, kAllForceTerms, 1)) {
    total += f;
    largest = norm(f) > norm(largest) ? f : largest;
  }
  EXPECT_LT(norm(total), 1e-10 * norm(largest));
}

TEST(Forces, TotalForceIsMinusGradientOfPotentialEnergy) {
  const ClothModel model = paper_lattice(4, 5);
  const std::vector<Vec3> x = perturbed(model, 0.3, 4);
  const std::vector<Vec3> v(model.particle_count());
  const std::vector<Vec3> f = evaluate(model, x, v, kAllForceTerms, 1);
  const double h = 1e-6;
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<Vec3> plus = x, minus = x;
      (axis == 0 ? plus[p].x : axis == 1 ? plus[p].y : plus[p].z) += h;
      (axis == 0 ? minus[p].x : axis == 1 ? minus[p].y : minus[p].z) -= h;
      const double gradient = (potential_energy(model, plus) - potential_energy(model, minus)) / (2 * h);
      EXPECT_NEAR(f[p][axis], -gradient, 1e-5 * (1 + std::abs(gradient)))
          << model.describe_particle(p) << " axis " << axis;
    }
  }
}

TEST(Forces, DampingPowerIsTheDampingForcesWork) {
  const ClothModel model = paper_lattice(5, 4, {0, -9.81, 0}, 0.3);
  TestRandom random(5);
  const std::vector<Vec3> x = perturbed(model, 0.2, 6);
  std::vector<Vec3> v(model.particle_count());
  for (Vec3& vi : v) vi = random.vector(-2, 2);
  ForcePowers powers;
  const std::vector<Vec3> with = evaluate(model, x, v, kAllForceTerms, 1, &powers);
  const std::vector<Vec3> without = evaluate(model, x, v, kAllForceTerms & ~kSpringDamping & ~kAirDrag, 1);
  double dissipative = 0.0;
  for (std::size_t p = 0; p < model.particle_count(); ++p) dissipative += dot(with[p] - without[p], v[p]);
  EXPECT_NEAR(powers.damping + powers.drag, dissipative, 1e-9 * std::abs(dissipative));
  EXPECT_LT(powers.damping, 0.0);
  double speed_squared = 0.0;
  for (const Vec3& vi : v) speed_squared += squared_norm(vi);
  EXPECT_NEAR(powers.drag, -0.3 * speed_squared, 1e-12 * speed_squared);
}

TEST(Forces, ResultIsBitIdenticalForAnyThreadCount) {
  const ClothModel model = paper_lattice(40, 37);
  TestRandom random(7);
  const std::vector<Vec3> x = perturbed(model, 0.3, 8);
  std::vector<Vec3> v(model.particle_count());
  for (Vec3& vi : v) vi = random.vector(-1, 1);
  ForcePowers reference_powers;
  const std::vector<Vec3> reference = evaluate(model, x, v, kAllForceTerms, 1, &reference_powers);
  for (int threads : {2, 3, 4}) {
    ForcePowers powers;
    const std::vector<Vec3> f = evaluate(model, x, v, kAllForceTerms, threads, &powers);
    EXPECT_EQ(std::memcmp(f.data(), reference.data(), f.size() * sizeof(Vec3)), 0) << threads << " threads";
    EXPECT_EQ(powers.damping, reference_powers.damping) << threads << " threads";
  }
}

TEST(Forces, TermMaskSwitchesTermsOff) {
  // Moving particles and air drag, so that the damping and drag bits have something to switch.
  const ClothModel model = paper_lattice(4, 4, {0, -9.81, 0}, 0.7);
  const std::vector<Vec3> x = perturbed(model, 0.3, 9);
  TestRandom random(10);
  std::vector<Vec3> v(model.particle_count());
  for (Vec3& vi : v) vi = random.vector(-2, 2);
  const std::vector<Vec3> all = evaluate(model, x, v, kAllForceTerms, 1);
  // The terms add up: each spring family with its damping, gravity and drag.
  std::vector<Vec3> sum(model.particle_count());
  for (ForceTerms term : {kGravity, kConnectorSprings | kSpringDamping, kAdjacentRadialSprings | kSpringDamping,
                          kOppositeRadialSprings | kSpringDamping, kAirDrag}) {
    const std::vector<Vec3> part = evaluate(model, x, v, term, 1);
    for (std::size_t p = 0; p < sum.size(); ++p) sum[p] += part[p];
  }
  for (std::size_t p = 0; p < sum.size(); ++p) {
    EXPECT_NEAR(norm(sum[p] - all[p]), 0.0, 1e-9 * (1 + norm(all[p])));
  }
  // Each bit changes the force of a moving, deformed sheet: none is ignored.
  for (ForceTerms term :
       {kGravity, kConnectorSprings, kAdjacentRadialSprings, kOppositeRadialSprings, kAirDrag, kSpringDamping}) {
    const std::vector<Vec3> without = evaluate(model, x, v, kAllForceTerms & ~term, 1);
    double change = 0.0;
    for (std::size_t p = 0; p < without.size(); ++p) change = std::max(change, norm(without[p] - all[p]));
    EXPECT_GT(change, 1e-6) << "term bit " << term;
  }
  // Drag alone is -c v on every particle.
  const std::vector<Vec3> drag = evaluate(model, x, v, kAirDrag, 1);
  for (std::size_t p = 0; p < drag.size(); ++p) EXPECT_EQ(drag[p], -0.7 * v[p]);
  EXPECT_EQ(evaluate(model, x, v, 0, 1)[0], Vec3{});
}

}  // namespace
}  // namespace clothsim
