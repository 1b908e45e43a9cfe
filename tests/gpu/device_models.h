// What the device's tests build their runs from (test_device_integrator.cpp,
// test_device_obstacles.cpp, test_device_state_checks.cpp): the Vulkan backend in a precision, and
// the paper's sheet as a model.
#pragma once

#include "model/cloth_model.h"
#include "sim/backend.h"

namespace clothsim::testing {

// Device 0 in `precision`.
inline BackendSettings vulkan(Precision precision) {
  return BackendSettings{Backend::vulkan, 0, request(precision)};
}

// A rows x cols lattice of the paper's material: 1 kg, (4, 1), (1400, 200), (80, 5), L = 1, under
// gravity, nothing anchored.
inline ClothModel paper_lattice(int rows, int cols) {
  LatticeDef lattice;
  lattice.rows = rows;
  lattice.cols = cols;
  return build_lattice(lattice, Environment{{0, -9.81, 0}, 0.0}, {});
}

}  // namespace clothsim::testing
