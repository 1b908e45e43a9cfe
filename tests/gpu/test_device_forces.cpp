// The general force path on the device (gpu/device_forces.h) against evaluate_forces on the
// CPU's general path, for a perturbed, moving sheet of the paper's material with gravity and air
// drag, with broken springs, and with terms switched off. Per particle, the difference is held
// against the particle's force scale: the sum of the magnitudes of what it gathers (its element
// slots on the CPU, m |g|, drag |v|). float64: 16 eps (the element passes agree to ~2 eps, and
// the sum is taken in the same order; measured 1.2 eps). float32, on float-rounded inputs: 32
// eps_f (measured 3.5 eps_f).
#include "gpu/device_forces.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "forces/forces.h"
#include "gpu_fixture.h"
#include "test_support.h"

namespace clothsim {
namespace {

using testing::GpuTest;
using testing::TestRandom;

ClothModel paper_lattice(int rows, int cols, double drag) {
  LatticeDef lattice;  // the paper's material: 1 kg, (4, 1), (1400, 200), (80, 5), L = 1
  lattice.rows = rows;
  lattice.cols = cols;
  return build_lattice(lattice, Environment{{0, -9.81, 0}, drag}, {});
}

// A value rounded to float and back. Through a volatile float: GCC 12 at -O3 dropped the round
// trip (double)(float) of the x and y components here (only z's conversions were left in the
// code), and the CPU then evaluated unrounded inputs (a sanitizer build at -O1 rounded them).
double round_to_float(double value) {
  const volatile float rounded = static_cast<float>(value);
  return rounded;
}
Vec3 round_to_float(const Vec3& v) { return {round_to_float(v.x), round_to_float(v.y), round_to_float(v.z)}; }

struct SheetState {
  std::vector<Vec3> position, velocity;
};

SheetState moving_sheet(const ClothModel& model, std::uint64_t seed, bool float_values) {
  TestRandom random(seed);
  SheetState state{model.particle_rest_position, std::vector<Vec3>(model.particle_count())};
  for (std::size_t p = 0; p < state.position.size(); ++p) {
    state.position[p] += random.vector(-0.3, 0.3);
    state.velocity[p] = random.vector(-1, 1);
    if (float_values) {
      state.position[p] = round_to_float(state.position[p]);
      state.velocity[p] = round_to_float(state.velocity[p]);
    }
  }
  return state;
}

// The largest per-particle difference over the particle's force scale; and the damping power's
// difference over the sum of the elements' powers, into *largest_power_difference if larger.
double largest_difference(const ClothModel& model, const SheetState& state, ForceTerms terms, gpu::Precision precision,
                          gpu::Device& device, double* largest_power_difference) {
  ForceBuffers buffers;
  buffers.kernel = ForceKernel::general;
  buffers.resize(model);
  std::vector<Vec3> cpu(model.particle_count());
  const ForcePowers cpu_powers = evaluate_forces(model, state.position, state.velocity, terms, 1, buffers, cpu);

  gpu::DeviceForces device_forces(device, model, precision, terms);
  std::vector<Vec3> gpu(model.particle_count());
  const double gpu_damping_power = device_forces.evaluate(model, state.position, state.velocity, gpu);

  // The damping power: the same fixed blocks summed in the same order; against the sum of the
  // elements' magnitudes, since the terms cancel nowhere (each is <= 0).
  double power_scale = std::numeric_limits<double>::min();
  for (double power : buffers.element_power) power_scale += std::abs(power);
  const double power_difference = std::abs(gpu_damping_power - cpu_powers.damping) / power_scale;
  if (power_difference > *largest_power_difference) *largest_power_difference = power_difference;

  const Vec3 gravity = (terms & kGravity) != 0 ? model.environment.gravity : Vec3{};
  const double drag = (terms & kAirDrag) != 0 ? model.environment.air_drag : 0.0;
  double worst = 0.0;
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    double scale = model.particle_mass[p] * norm(gravity) + drag * norm(state.velocity[p]);
    for (std::uint32_t k = buffers.gather.offset[p]; k < buffers.gather.offset[p + 1]; ++k) {
      scale += norm(buffers.slot_force[buffers.gather.slot[k]]);
    }
    const double difference = norm(gpu[p] - cpu[p]);
    EXPECT_TRUE(std::isfinite(difference)) << "particle " << p;
    if (difference > 0.0) worst = std::max(worst, difference / scale);
  }
  return worst;
}

constexpr double kEpsilon64 = std::numeric_limits<double>::epsilon();
constexpr double kEpsilon32 = std::numeric_limits<float>::epsilon();

TEST_F(GpuTest, SheetForcesFloat64MatchEvaluateForces) {
  const ClothModel model = paper_lattice(40, 37, 0.3);
  const SheetState state = moving_sheet(model, 7, false);
  double power = 0.0;
  const double difference = largest_difference(model, state, kAllForceTerms, gpu::Precision::float64, device(), &power);
  std::printf("float64 sheet, 40 x 37: forces within %.3g eps of the particle's force scale, damping power %.3g eps\n",
              difference / kEpsilon64, power / kEpsilon64);
  EXPECT_LE(difference, 16 * kEpsilon64);
  EXPECT_LE(power, 16 * kEpsilon64);
}

TEST_F(GpuTest, SheetForcesFloat32MatchEvaluateForces) {
  const ClothModel model = paper_lattice(40, 37, 0.3);
  const SheetState state = moving_sheet(model, 8, true);
  double power = 0.0;
  const double difference = largest_difference(model, state, kAllForceTerms, gpu::Precision::float32, device(), &power);
  std::printf(
      "float32 sheet, 40 x 37: forces within %.3g eps_f of the particle's force scale, damping power %.3g eps_f\n",
      difference / kEpsilon32, power / kEpsilon32);
  EXPECT_LE(difference, 32 * kEpsilon32);
  EXPECT_LE(power, 32 * kEpsilon32);
}

TEST_F(GpuTest, SheetForcesFollowBrokenSpringsAndTheTermMask) {
  ClothModel model = paper_lattice(12, 9, 0.0);
  // Broken springs: every 7th connector and every 5th radial spring, marked as the event stage
  // would leave them (the forces read only the live flags).
  for (std::size_t e = 0; e < model.connector_count(); e += 7) model.connector_live[e] = 0;
  for (std::size_t r = 0; r < model.radial_count(); r += 5) model.radial_live[r] = 0;
  const SheetState state = moving_sheet(model, 9, false);
  for (ForceTerms terms : {kAllForceTerms, kConnectorSprings | kOppositeRadialSprings,
                           kGravity | kAdjacentRadialSprings | kSpringDamping, ForceTerms{0}}) {
    double power = 0.0;
    const double difference = largest_difference(model, state, terms, gpu::Precision::float64, device(), &power);
    EXPECT_LE(difference, 16 * kEpsilon64) << "terms " << terms;
    EXPECT_LE(power, 16 * kEpsilon64) << "terms " << terms;
  }
}

}  // namespace
}  // namespace clothsim
