// Helpers shared by the scene tests.
#pragma once

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>
#include <string_view>

#include "core/error.h"
#include "scene/parameters.h"
#include "scene/scene.h"

namespace clothsim::testing {

// Runs `action`, which must throw an InputError whose message contains every piece.
template <typename Action>
void expect_input_error(Action action, std::initializer_list<std::string_view> pieces) {
  try {
    action();
  } catch (const InputError& error) {
    const std::string message = error.what();
    for (std::string_view piece : pieces) {
      EXPECT_NE(message.find(piece), std::string::npos) << "message: " << message << "\nmissing: " << piece;
    }
    return;
  }
  ADD_FAILURE() << "no InputError thrown";
}

inline void expect_same_vector(const Vec3& a, const Vec3& b, const std::string& what) {
  EXPECT_EQ(a.x, b.x) << what;
  EXPECT_EQ(a.y, b.y) << what;
  EXPECT_EQ(a.z, b.z) << what;
}

// Field-for-field equality of two scenes: every registry parameter, vector and hand-parsed field.
// Rest angles are compared in radians, bit for bit.
inline void expect_same_scene(const SceneSpec& a, const SceneSpec& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.description, b.description);
  for (const ScalarParameter& parameter : scalar_parameters()) {
    EXPECT_EQ(parameter.get(a), parameter.get(b)) << parameter.key;
  }
  for (const VectorParameter& parameter : vector_parameters()) {
    expect_same_vector(parameter.get(a), parameter.get(b), std::string(parameter.key));
  }
  EXPECT_EQ(a.lattice.adjacent_rest_angle, b.lattice.adjacent_rest_angle);
  EXPECT_EQ(a.lattice.opposite_rest_angle, b.lattice.opposite_rest_angle);
  EXPECT_EQ(a.integrator.kind, b.integrator.kind);
  ASSERT_EQ(a.anchors.size(), b.anchors.size());
  for (std::size_t i = 0; i < a.anchors.size(); ++i) {
    const AnchorSpec& x = a.anchors[i];
    const AnchorSpec& y = b.anchors[i];
    const std::string what = "anchors[" + std::to_string(i) + "]";
    EXPECT_EQ(x.row, y.row) << what;
    EXPECT_EQ(x.col, y.col) << what;
    EXPECT_EQ(x.origin_given, y.origin_given) << what;
    EXPECT_EQ(x.path.kind, y.path.kind) << what;
    expect_same_vector(x.path.origin, y.path.origin, what + ".origin");
    expect_same_vector(x.path.velocity, y.path.velocity, what + ".velocity");
    expect_same_vector(x.path.amplitude, y.path.amplitude, what + ".amplitude");
    EXPECT_EQ(x.path.frequency, y.path.frequency) << what;
    EXPECT_EQ(x.path.phase, y.path.phase) << what;
    EXPECT_EQ(x.path.keys, y.path.keys) << what;
    EXPECT_EQ(x.release_time, y.release_time) << what;
  }
  EXPECT_EQ(a.lattice.limits, b.lattice.limits);
  EXPECT_EQ(a.material, b.material);
  ASSERT_EQ(a.colliders.size(), b.colliders.size());
  for (std::size_t i = 0; i < a.colliders.size(); ++i) {
    const Collider& x = a.colliders[i].collider;
    const Collider& y = b.colliders[i].collider;
    const std::string what = "colliders[" + std::to_string(i) + "]";
    EXPECT_EQ(x.shape, y.shape) << what;
    expect_same_vector(x.point, y.point, what + ".point");
    expect_same_vector(x.normal, y.normal, what + ".normal");
    expect_same_vector(x.center, y.center, what + ".center");
    EXPECT_EQ(x.radius, y.radius) << what;
    expect_same_vector(x.half_extents, y.half_extents, what + ".half_extents");
    expect_same_vector(x.a, y.a, what + ".a");
    expect_same_vector(x.b, y.b, what + ".b");
    EXPECT_EQ(x.friction, y.friction) << what;
    EXPECT_EQ(x.path.kind, y.path.kind) << what;
    expect_same_vector(x.path.velocity, y.path.velocity, what + ".path.velocity");
    expect_same_vector(x.path.amplitude, y.path.amplitude, what + ".path.amplitude");
    EXPECT_EQ(x.path.frequency, y.path.frequency) << what;
    EXPECT_EQ(x.path.keys, y.path.keys) << what;
    EXPECT_EQ(a.colliders[i].mesh_file, b.colliders[i].mesh_file) << what;
    EXPECT_EQ(a.colliders[i].mesh_scale, b.colliders[i].mesh_scale) << what;
    expect_same_vector(a.colliders[i].mesh_translate, b.colliders[i].mesh_translate, what + ".translate");
    EXPECT_EQ(x.mesh == nullptr, y.mesh == nullptr) << what;
    if (x.mesh != nullptr && y.mesh != nullptr) {
      EXPECT_EQ(x.mesh->vertex, y.mesh->vertex) << what;
    }
  }
  EXPECT_EQ(a.collision.thickness, b.collision.thickness);
  EXPECT_EQ(a.collision.self, b.collision.self);
  EXPECT_EQ(a.collision.friction, b.collision.friction);
}

}  // namespace clothsim::testing
