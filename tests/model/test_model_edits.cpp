// Obstacles moved by hand (model/model_edits.h): drive_collider moves every shape but meshes in a
// straight line from where it is, whatever path it had, as its path (so the collision stage sees
// the velocity), and stops at the arrival; place_collider moves it at once and holds it.
#include <gtest/gtest.h>

#include <vector>

#include "model/model_edits.h"

namespace clothsim {
namespace {

// One collider of each shape that can be moved by hand, on a linear scene path.
std::vector<Collider> moving_shapes() {
  Collider plane;
  plane.shape = ColliderShape::plane;
  plane.point = {0.0, -1.0, 0.0};
  Collider sphere;
  sphere.shape = ColliderShape::sphere;
  sphere.center = {1.0, 2.0, 3.0};
  sphere.radius = 0.5;
  Collider box;
  box.shape = ColliderShape::box;
  box.center = {-1.0, 0.0, 2.0};
  box.half_extents = {0.5, 0.25, 1.0};
  Collider capsule;
  capsule.shape = ColliderShape::capsule;
  capsule.a = {0.0, 0.0, 0.0};
  capsule.b = {1.0, 1.0, 0.0};
  capsule.radius = 0.2;
  std::vector<Collider> shapes = {plane, sphere, box, capsule};
  for (Collider& shape : shapes) {
    shape.path.kind = AnchorPathKind::linear;
    shape.path.velocity = {0.5, -0.25, 1.0};
  }
  return shapes;
}

TEST(ModelEdits, ADrivenColliderMovesInAStraightLineFromWhereItIsAndStops) {
  const Vec3 displacement{0.6, 0.3, -0.9};
  const double now = 1.5;
  const double arrival = 2.0;
  for (const Collider& shape : moving_shapes()) {
    ClothModel model;
    const std::size_t c = add_collider(model, shape);
    const Collider before = model.colliders[c];
    const std::uint64_t revision = model.revision;
    drive_collider(model, c, displacement, now, arrival);
    EXPECT_GT(model.revision, revision);
    const Collider& driven = model.colliders[c];
    // Probe points of the shape, carried along: the distance there is the same as before the
    // edit at `now`, then follows the displacement, and stays after the arrival.
    const std::vector<Vec3> probes = {{0.3, 0.1, -0.2}, {2.0, -1.0, 1.0}, {-1.0, 0.5, 2.5}};
    for (const Vec3& probe : probes) {
      const double at_now = signed_distance(before, probe, now).distance;
      EXPECT_NEAR(signed_distance(driven, probe, now).distance, at_now, 1e-12);
      EXPECT_NEAR(signed_distance(driven, probe + 0.5 * displacement, 1.75).distance, at_now, 1e-12);
      EXPECT_NEAR(signed_distance(driven, probe + displacement, arrival).distance, at_now, 1e-12);
      EXPECT_NEAR(signed_distance(driven, probe + displacement, 3.0).distance, at_now, 1e-12);
    }
    EXPECT_LT(norm(signed_distance(driven, probes[0], 1.75).velocity - displacement / 0.5), 1e-12);
    EXPECT_LT(norm(signed_distance(driven, probes[0], arrival).velocity - displacement / 0.5), 1e-12);
    EXPECT_EQ(signed_distance(driven, probes[0], 3.0).velocity, Vec3{});
  }
}

TEST(ModelEdits, APlacedColliderMovesAtOnceAndIsHeld) {
  const Vec3 displacement{-0.4, 0.2, 0.7};
  for (const Collider& shape : moving_shapes()) {
    ClothModel model;
    const std::size_t c = add_collider(model, shape);
    const Collider before = model.colliders[c];
    place_collider(model, c, displacement, 2.0);
    const Vec3 probe{0.3, 0.1, -0.2};
    const double at_now = signed_distance(before, probe, 2.0).distance;
    EXPECT_NEAR(signed_distance(model.colliders[c], probe + displacement, 2.0).distance, at_now, 1e-12);
    EXPECT_NEAR(signed_distance(model.colliders[c], probe + displacement, 5.0).distance, at_now, 1e-12);
    EXPECT_EQ(signed_distance(model.colliders[c], probe, 5.0).velocity, Vec3{});
  }
}

TEST(ModelEdits, TheSelfCollisionSwitchSetsTheFlagAndMovesTheRevision) {
  ClothModel model;
  const std::uint64_t revision = model.revision;
  set_self_collision(model, true);
  EXPECT_TRUE(model.collision.self);
  EXPECT_EQ(model.revision, revision + 1);
  set_self_collision(model, false);
  EXPECT_FALSE(model.collision.self);
}

}  // namespace
}  // namespace clothsim
