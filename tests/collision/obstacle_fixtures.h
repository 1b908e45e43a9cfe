// The obstacle tests' sheets, colliders and runs (collision/obstacle_contacts.h), for the CPU's
// tests (test_obstacle_contacts.cpp) and the same checks on the Vulkan backend
// (tests/gpu/test_device_obstacles.cpp): a small sheet of the paper's springs dropped on a
// collider, a fast particle, a sheet on a slope. Scenes are built through the library
// (build_lattice + colliders), not scene files.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "model/cloth_model.h"
#include "model/collider.h"
#include "model/mesh_fixtures.h"
#include "sim/backend.h"
#include "sim/simulation.h"

namespace clothsim::obstacle_fixtures {

inline constexpr double kThickness = 0.02;  // m
// How far inside the thickness shell a particle may be at a saved frame: the stage places it at
// exactly the thickness, so only rounding remains.
inline constexpr double kDepthTolerance = 1e-9;  // m
// How closely the energy balance closes over a drop: RKF45's integration error at tolerance 1e-6
// over the tens of thousands of steps a draped sheet takes (its potential energy is ~600 J).
inline constexpr double kBalanceTolerance = 1e-2;  // J

// A 7 x 7 sheet of spacing `spacing` (3 m wide by default) with the paper's springs, flat at
// height `height`.
inline ClothModel sheet(double height, std::vector<Collider> colliders, double friction = 0.3, double spacing = 0.5,
                        double opposite_damping = LatticeDef{}.opposite.damping) {
  LatticeDef def;
  def.rows = 7;
  def.cols = 7;
  def.spacing = spacing;
  def.opposite.damping = opposite_damping;
  ClothModel model = build_lattice(def, Environment{}, {});
  for (Vec3& x : model.particle_rest_position) x.y = height;
  model.colliders = std::move(colliders);
  model.collision.thickness = kThickness;
  model.collision.friction = friction;
  return model;
}

inline ClothState rest_state(const ClothModel& model) {
  ClothState state = make_rest_state(model);
  for (std::size_t p = 0; p < model.particle_count(); ++p) state.position[p] = model.particle_rest_position[p];
  return state;
}

inline SimulationSettings settings(int threads = 1) {
  SimulationSettings s;
  s.integrator.relative_tolerance = 1e-6;
  s.integrator.absolute_tolerance = 1e-6;
  s.threads = threads;
  return s;
}

inline Collider plane(const Vec3& point, const Vec3& normal) {
  Collider c;
  c.shape = ColliderShape::plane;
  c.point = point;
  c.normal = normal;
  return c;
}

inline Collider sphere(const Vec3& center, double radius) {
  Collider c;
  c.shape = ColliderShape::sphere;
  c.center = center;
  c.radius = radius;
  return c;
}

inline Collider box(const Vec3& center, const Vec3& half_extents) {
  Collider c;
  c.shape = ColliderShape::box;
  c.center = center;
  c.half_extents = half_extents;
  return c;
}

inline Collider capsule(const Vec3& a, const Vec3& b, double radius) {
  Collider c;
  c.shape = ColliderShape::capsule;
  c.a = a;
  c.b = b;
  c.radius = radius;
  return c;
}

// A triangle mesh collider (a cube here: the same table as the box case, through the mesh path).
inline Collider mesh_collider(std::shared_ptr<const TriangleMesh> mesh) {
  Collider c;
  c.shape = ColliderShape::mesh;
  c.mesh = std::move(mesh);
  c.mesh_file = "cube (built in code)";
  return c;
}

// The collider moving at `velocity` (m/s) from where it is.
inline Collider moving(Collider collider, const Vec3& velocity) {
  collider.path.kind = AnchorPathKind::linear;
  collider.path.origin = Vec3{0.0, 0.0, 0.0};
  collider.path.velocity = velocity;
  return collider;
}

// The deepest any particle is inside the thickness shell of any collider, m (<= 0 when none is).
inline double deepest(const Simulation& simulation) {
  const ClothModel& model = simulation.model();
  const ClothState& state = simulation.state();
  double depth = -1.0;
  for (const Collider& collider : model.colliders) {
    for (std::size_t p = 0; p < model.particle_count(); ++p) {
      const double d = signed_distance(collider, state.position[p], state.time).distance;
      depth = std::max(depth, kThickness - d);
    }
  }
  return depth;
}

struct DropResult {
  double deepest = -1.0;  // m, over every saved frame
  double contact_work = 0.0;
  double balance_error = 0.0;
  double final_kinetic = 0.0;
  std::uint64_t contact_steps = 0;
  std::vector<Vec3> final_position;  // m
};

// Drops the sheet for `duration` s with `run_settings`, checking every frame (30 per second).
inline DropResult drop(ClothModel model, double duration, const SimulationSettings& run_settings = settings()) {
  ClothState state = rest_state(model);
  Simulation simulation(std::move(model), std::move(state), run_settings);
  DropResult result;
  const int frames = static_cast<int>(std::lround(duration * 30.0));
  for (int frame = 1; frame <= frames; ++frame) {
    EXPECT_TRUE(simulation.advance_to(frame / 30.0)) << simulation.failure()->message;
    if (simulation.failure()) break;
    result.deepest = std::max(result.deepest, deepest(simulation));
  }
  const EnergyBalance balance = simulation.energy_balance();
  result.contact_work = balance.contact_work;
  result.balance_error = balance.error();
  result.final_kinetic = balance.energy.kinetic;
  result.contact_steps = simulation.contact_statistics().contact_steps;
  result.final_position = simulation.state().position;
  return result;
}

struct ColliderCase {
  const char* name;
  Collider collider;
  double height;  // m, the sheet's starting height
};

inline std::vector<ColliderCase> collider_cases() {
  return {
      {"plane", plane({0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}), 0.5},
      {"sphere", sphere({0.0, 0.0, 0.0}, 1.0), 1.3},
      {"box", box({0.0, 0.0, 0.0}, {0.8, 0.5, 0.8}), 0.8},
      {"capsule", capsule({-1.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, 0.5), 0.8},
      {"mesh", mesh_collider(cube_mesh({0.0, 0.0, 0.0}, {0.8, 0.5, 0.8})), 0.8},
  };
}

// Two particles (0.05 m apart) flying at 50 m/s towards a 0.1 m obstacle, with a fixed step in
// which they move 0.5 m: more than the obstacle's size.
inline void expect_no_tunnelling(const Collider& obstacle, double front, const BackendSettings& backend = {},
                                 double depth_tolerance = kDepthTolerance, double speed_tolerance = 1e-9) {
  LatticeDef def;
  def.rows = 2;
  def.cols = 1;
  def.spacing = 0.05;
  ClothModel model = build_lattice(def, Environment{{0.0, 0.0, 0.0}, 0.0}, {});
  model.colliders = {obstacle};
  model.collision.thickness = kThickness;
  ClothState state = make_rest_state(model);
  for (std::size_t p = 0; p < 2; ++p) {
    state.position[p].x = -1.0;
    state.velocity[p] = Vec3{50.0, 0.0, 0.0};
  }
  SimulationSettings s;
  s.integrator.kind = IntegratorKind::rk4;
  s.integrator.time_step = 0.01;
  s.threads = 1;
  s.backend = backend;
  Simulation simulation(std::move(model), std::move(state), s);
  for (int step = 1; step <= 10; ++step) {
    ASSERT_TRUE(simulation.advance_to(0.01 * step));
    for (const Vec3& x : simulation.state().position) {
      EXPECT_LT(x.x, front) << "step " << step << ": the particle passed through";
      EXPECT_GE(signed_distance(obstacle, x, simulation.state().time).distance, kThickness - depth_tolerance);
    }
  }
  // Caught at the entry point, its approaching velocity removed.
  for (const Vec3& v : simulation.state().velocity) EXPECT_LE(v.x, speed_tolerance);
}

// A sheet resting on a plane inclined by `angle` (rad) about z, friction mu = 0.5; returns how
// far its centre moved along the slope in `duration` s. Implicit Euler holds the resting sheet on
// the plane within its steps, and the friction comes from the impulse that took
// (model/surface_contacts.h); the explicit methods' comes from the projection's.
inline double slide_on_slope(double angle, double duration, IntegratorKind kind = IntegratorKind::rkf45,
                             const BackendSettings& backend = {},
                             double opposite_damping = LatticeDef{}.opposite.damping) {
  const Vec3 normal{-std::sin(angle), std::cos(angle), 0.0};
  Collider slope = plane({0.0, 0.0, 0.0}, normal);
  slope.friction = 0.5;
  ClothModel model = sheet(0.0, {slope}, 0.0, 0.5, opposite_damping);
  // Tilt the flat sheet onto the slope, at the thickness above it.
  for (Vec3& x : model.particle_rest_position) {
    const Vec3 flat = x;
    x = Vec3{flat.x * std::cos(angle), flat.x * std::sin(angle), flat.z} + kThickness * normal;
  }
  ClothState state = rest_state(model);
  const std::size_t centre = model.particle_count() / 2;
  const Vec3 start = state.position[centre];
  SimulationSettings s = settings();
  s.integrator.kind = kind;
  s.backend = backend;
  Simulation simulation(std::move(model), std::move(state), s);
  EXPECT_TRUE(simulation.advance_to(duration));
  EXPECT_LE(deepest(simulation), kDepthTolerance);
  return norm(simulation.state().position[centre] - start);
}


}  // namespace clothsim::obstacle_fixtures
