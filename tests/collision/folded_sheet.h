// A soft 16 x 16 sheet folded in half, its upper half 6 mm above the lower, above a floor, with
// self-collision on (thickness 4 mm): it falls onto the floor and onto itself. The self-collision
// tests' sheet (test_self_contacts.cpp), and the Vulkan backend's (tests/gpu).
#pragma once

#include <cstddef>
#include <utility>

#include "model/cloth_model.h"
#include "sim/backend.h"
#include "sim/simulation.h"

namespace clothsim::testing {

inline Simulation folded_sheet(IntegratorKind kind, double time_step, int threads,
                               const BackendSettings& backend = {}) {
  LatticeDef def;
  def.rows = 16;
  def.cols = 16;
  def.spacing = 0.03;
  def.particle_mass = 0.01;
  def.connector = {50.0, 0.1};
  def.adjacent = {0.01, 0.0};
  def.opposite = {0.01, 0.0};
  ClothModel model = build_lattice(def, Environment{}, {});
  model.environment.gravity = {0.0, -9.81, 0.0};
  Collider floor;
  floor.shape = ColliderShape::plane;
  floor.point = {0.0, -0.005, 0.0};
  floor.normal = {0.0, 1.0, 0.0};
  model.colliders = {floor};
  model.collision.self = true;
  model.collision.thickness = 0.004;
  SimulationSettings settings;
  settings.integrator.kind = kind;
  settings.integrator.time_step = time_step;
  settings.threads = threads;
  settings.backend = backend;
  ClothState initial = make_rest_state(model);
  for (int row = 8; row < 16; ++row) {
    for (int col = 0; col < 16; ++col) {
      Vec3& x = initial.position[static_cast<std::size_t>(row * 16 + col)];
      x = {x.x, 0.006, initial.position[static_cast<std::size_t>((15 - row) * 16 + col)].z};
    }
  }
  return Simulation(std::move(model), std::move(initial), settings);
}

}  // namespace clothsim::testing
