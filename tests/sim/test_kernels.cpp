// Whole runs with each force kernel: bit-for-bit the same result for 1, 2, 3 and 4 threads with
// the general and with the lattice kernel, and the two kernels giving the same motion up to
// rounding.
#include <gtest/gtest.h>

#include <cstring>
#include <optional>

#include "model/initial_conditions.h"
#include "sim/simulation.h"

namespace clothsim {
namespace {

ClothState run(ForceKernel kernel, int threads, std::optional<PrecisionRequest> precision = std::nullopt) {
  LatticeDef def;  // the paper's material, damped
  def.rows = 40;   // 1,280 particles: 5 bands of the lattice kernel's radial and gather passes
  def.cols = 32;
  const Anchor anchor{lattice_index(def.cols, 20, 16), AnchorPath::fixed_at({0.0, 0.0, 0.5})};
  ClothModel model = build_lattice(def, Environment{{0.0, -9.81, 0.0}, 0.05}, {&anchor, 1});
  ClothState state = make_rest_state(model);
  InitialConditions initial;
  initial.position_noise = 0.02;
  initial.velocity_noise = 0.1;
  initial.seed = 11;
  apply_initial_conditions(model, initial, state);
  SimulationSettings settings;
  settings.threads = threads;
  settings.kernel = kernel;
  settings.backend.precision = precision;
  Simulation simulation(std::move(model), std::move(state), settings);
  EXPECT_EQ(simulation.threads(), threads);
  EXPECT_TRUE(simulation.advance_to(0.006));
  return simulation.state();
}

TEST(Kernels, EachKernelIsBitIdenticalForAnyThreadCount) {
  for (ForceKernel kernel : {ForceKernel::general, ForceKernel::lattice}) {
    const ClothState one = run(kernel, 1);
    for (int threads : {2, 3, 4}) {
      const ClothState many = run(kernel, threads);
      const auto bytes = one.position.size() * sizeof(Vec3);
      EXPECT_EQ(std::memcmp(one.position.data(), many.position.data(), bytes), 0) << threads << " threads";
      EXPECT_EQ(std::memcmp(one.velocity.data(), many.velocity.data(), bytes), 0) << threads << " threads";
      EXPECT_EQ(one.damping_work, many.damping_work) << threads << " threads";
      EXPECT_EQ(one.time, many.time);
    }
  }
}

TEST(Kernels, LatticeAndGeneralKernelsGiveTheSameMotion) {
  // In float64 (the lattice kernel on `auto`, the default, takes float32 forces where they agree).
  const ClothState general = run(ForceKernel::general, 1, PrecisionRequest::float64);
  const ClothState lattice = run(ForceKernel::lattice, 1, PrecisionRequest::float64);
  double largest = 0.0;
  for (std::size_t p = 0; p < general.position.size(); ++p) {
    largest = std::max(largest, norm(general.position[p] - lattice.position[p]));
  }
  // Rounding-level differences in the forces, far below the 1e-6 m error tolerance of the run.
  EXPECT_LT(largest, 1e-10);
  EXPECT_NEAR(general.damping_work, lattice.damping_work, 1e-9 * std::abs(general.damping_work));
}

}  // namespace
}  // namespace clothsim
