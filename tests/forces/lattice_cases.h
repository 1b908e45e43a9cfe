// Sheets and states the force tests share (test_lattice_kernel.cpp, test_float32_forces.cpp): a
// lattice of the paper's material, random states around its rest shape, and a torn and changed
// sheet.
#pragma once

#include <algorithm>
#include <cstdint>
#include <numbers>
#include <vector>

#include "model/cloth_model.h"
#include "model/model_edits.h"
#include "test_support.h"

namespace clothsim::testing {

inline ClothModel lattice(int rows, int cols, double drag = 0.0) {
  LatticeDef def;  // the paper's material
  def.rows = rows;
  def.cols = cols;
  return build_lattice(def, Environment{{0.0, -9.81, 0.0}, drag}, {});
}

// Random positions around the rest lattice (amplitude in m) and random velocities.
inline void randomise(const ClothModel& model, double amplitude, double speed, std::uint64_t seed,
                      std::vector<Vec3>& x, std::vector<Vec3>& v) {
  TestRandom random(seed);
  x = model.particle_rest_position;
  v.assign(model.particle_count(), Vec3{});
  for (std::size_t p = 0; p < x.size(); ++p) {
    x[p] += random.vector(-amplitude, amplitude);
    v[p] = random.vector(-speed, speed);
  }
}

// A sheet that has torn and changed: `broken_fraction` of its connectors broken (through the
// model's seam, which takes their radial springs along), and every spring's stiffness, damping and
// rest value different, as plasticity, creasing and a varying material make them.
inline ClothModel torn_and_plastic(int rows, int cols, double broken_fraction, std::uint64_t seed) {
  ClothModel model = lattice(rows, cols, 0.2);
  TestRandom random(seed);
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    model.connector_rest_length[e] *= random.uniform(0.8, 1.3);
    model.connector_stiffness[e] *= random.uniform(0.5, 1.5);
    model.connector_damping[e] *= random.uniform(0.5, 1.5);
  }
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    model.radial_rest_angle[r] =
        std::clamp(model.radial_rest_angle[r] + random.uniform(-0.6, 0.6), 0.0, std::numbers::pi);
    model.radial_stiffness[r] *= random.uniform(0.5, 1.5);
    model.radial_damping[r] *= random.uniform(0.5, 1.5);
  }
  ++model.revision;
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    if (random.uniform(0.0, 1.0) < broken_fraction) break_connector(model, static_cast<std::uint32_t>(e));
  }
  return model;
}

// Moves every third particle of x towards its east neighbour (its west one in the last column),
// so that the connector between them is 2 % to 45 % of its original length: inside the fade of
// the radial springs on it (forces/element_math.inc, kRadialFadeFraction). Returns how many
// connectors it shortened.
inline int collapse_connectors(const ClothModel& model, std::vector<Vec3>& x, std::uint64_t seed) {
  TestRandom random(seed);
  int count = 0;
  for (std::size_t p = 0; p < x.size(); p += 3) {
    if (model.cols < 2) break;
    const bool last = static_cast<int>(p % static_cast<std::size_t>(model.cols)) == model.cols - 1;
    const std::size_t q = last ? p - 1 : p + 1;
    const Vec3 arm = x[p] - x[q];
    const double length = random.uniform(0.02, 0.45) * model.spacing;
    x[p] = x[q] + (length / norm(arm)) * arm;
    ++count;
  }
  return count;
}

}  // namespace clothsim::testing
