// The Vulkan backend's integrator (gpu/device_integrator.h) against the CPU's integrators.
#include "gpu/device_integrator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "integrators/integrator.h"
#include "model/cloth_model.h"
#include "test_support.h"

namespace clothsim {
namespace {

ClothModel paper_lattice(int rows, int cols) {
  LatticeDef lattice;  // the paper's material: 1 kg, (4, 1), (1400, 200), (80, 5), L = 1
  lattice.rows = rows;
  lattice.cols = cols;
  ClothModel model = build_lattice(lattice, Environment{{0, -9.81, 0}, 0.0}, {});
  return model;
}

ClothState rest_state(const ClothModel& model) {
  ClothState state;
  state.position = model.particle_rest_position;
  state.velocity.assign(model.particle_count(), Vec3{});
  return state;
}

double largest_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double largest = 0.0;
  for (std::size_t p = 0; p < a.size(); ++p) largest = std::max(largest, norm(a[p] - b[p]));
  return largest;
}

TEST(DeviceIntegrator, OneStepMatchesTheCpu) {
  const ClothModel model = paper_lattice(9, 9);
  for (IntegratorKind kind : {IntegratorKind::symplectic_euler, IntegratorKind::rk4, IntegratorKind::rkf45}) {
    IntegratorSettings settings;
    settings.kind = kind;
    settings.time_step = 1e-4;
    ClothState cpu = rest_state(model);
    cpu.velocity[3] = {0.1, 0.2, 0.3};
    ClothState device = cpu;
    const ForceOptions options;
    std::unique_ptr<Integrator> reference = make_integrator(model, settings, options);
    gpu::DeviceIntegrator integrator(model, settings, options, gpu::DeviceSelection{0, Precision::float64, true});
    ASSERT_EQ(reference->step(cpu, 1.0).status, StepStatus::ok);
    ASSERT_EQ(integrator.step(device, 1.0).status, StepStatus::ok);
    EXPECT_EQ(cpu.time, device.time) << to_string(kind);
    EXPECT_LT(largest_distance(cpu.position, device.position), 1e-12) << to_string(kind);
    EXPECT_LT(largest_distance(cpu.velocity, device.velocity), 1e-12) << to_string(kind);
  }
}

}  // namespace
}  // namespace clothsim
