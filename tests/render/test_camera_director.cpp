// Tests of render/camera_director: automatic framing never zooms in and keeps every frame in
// view; follow glides (no jumps) and catches up with a falling sheet; fixed does not move; the
// ground stays below everything seen; bounded colliders are framed, planes are not.
#include "render/camera_director.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "model/collider.h"

namespace clothsim::render {
namespace {

ClothModel sheet() { return build_lattice(LatticeDef{.rows = 6, .cols = 6, .spacing = 0.2}, Environment{}, {}); }

// The sheet at time t: falling freely from rest and swinging sideways.
std::vector<Vec3> falling(const ClothModel& model, double t) {
  std::vector<Vec3> position = model.particle_rest_position;
  for (Vec3& p : position) p += Vec3{0.3 * std::sin(3.0 * t), -0.5 * 9.81 * t * t, 0.0};
  return position;
}

bool all_visible(const Camera& camera, const std::vector<Vec3>& points) {
  for (const Vec3& p : points) {
    if (!camera.project(p, 160, 90).visible) return false;
  }
  return true;
}

TEST(CameraDirector, AutomaticKeepsEverythingInViewAndNeverZoomsIn) {
  const ClothModel model = sheet();
  CameraDirector director(CameraChoice{}, 16.0 / 9.0);
  double previous_distance = 0.0;
  double previous_ground = 1e9;
  for (int frame = 0; frame <= 30; ++frame) {
    const double t = frame / 30.0;
    const std::vector<Vec3> position = falling(model, t);
    director.update(model, position, t);
    EXPECT_TRUE(all_visible(director.camera(), position)) << "frame " << frame;
    EXPECT_TRUE(all_visible(director.camera(), falling(model, 0.0))) << "the start stays in view, frame " << frame;
    EXPECT_GE(director.camera().distance, previous_distance * (1.0 - 1e-12));
    previous_distance = director.camera().distance;
    for (const Vec3& p : position) EXPECT_LT(director.ground_height(), p.y);
    EXPECT_LE(director.ground_height(), previous_ground);
    previous_ground = director.ground_height();
  }
}

TEST(CameraDirector, FollowGlidesAfterAFallingSheet) {
  const ClothModel model = sheet();
  CameraChoice choice;
  choice.mode = CameraMode::follow;
  CameraDirector director(choice, 16.0 / 9.0);
  double previous_target_y = 0.0;
  const double fps = 60.0;
  for (int frame = 0; frame <= 120; ++frame) {
    const double t = frame / fps;
    const std::vector<Vec3> position = falling(model, t);
    director.update(model, position, t);
    EXPECT_TRUE(all_visible(director.camera(), position)) << "frame " << frame;
    const double target_y = director.camera().target.y;
    if (frame > 0) {
      // Smooth: the target moves by less per frame than the sheet does (v = g t).
      EXPECT_LE(previous_target_y - target_y, 9.81 * t / fps + 1e-12) << "frame " << frame;
      EXPECT_LE(target_y, previous_target_y + 1e-12) << "frame " << frame;
    }
    previous_target_y = target_y;
  }
  // After 2 s the sheet is 19.6 m down, falling at 19.6 m/s: the camera has followed it most of
  // the way and sees it, closer than automatic framing, which shows the whole drop.
  const std::vector<Vec3> last = falling(model, 2.0);
  EXPECT_LT(director.camera().target.y, -12.0);
  EXPECT_TRUE(all_visible(director.camera(), last));
  CameraDirector automatic(CameraChoice{}, 16.0 / 9.0);
  for (int frame = 0; frame <= 120; ++frame) automatic.update(model, falling(model, frame / fps), frame / fps);
  EXPECT_LT(director.camera().distance, 0.5 * automatic.camera().distance);
}

TEST(CameraDirector, FixedDoesNotMove) {
  const ClothModel model = sheet();
  CameraChoice choice;
  choice.mode = CameraMode::fixed;
  choice.distance = 7.0;
  CameraDirector director(choice, 1.0);
  director.update(model, falling(model, 0.0), 0.0);
  const Camera first = director.camera();
  EXPECT_DOUBLE_EQ(first.distance, 7.0);
  director.update(model, falling(model, 0.5), 0.5);
  EXPECT_EQ(director.camera().target, first.target);
  EXPECT_DOUBLE_EQ(director.camera().distance, 7.0);
}

}  // namespace
}  // namespace clothsim::render

namespace clothsim::render {
namespace {

// A bounded collider counts as seen, where its path puts it: the obstacle under a sheet is in the
// picture, and the ground stays below it. Planes are unbounded and do not change the framing.
TEST(CameraDirector, AutomaticFramesBoundedColliders) {
  ClothModel model = sheet();
  Collider floor;
  floor.shape = ColliderShape::plane;
  floor.point = {0.0, -50.0, 0.0};
  model.colliders.push_back(floor);
  Collider sphere;
  sphere.shape = ColliderShape::sphere;
  sphere.center = {0.0, -2.0, 0.0};
  sphere.radius = 0.5;
  sphere.path.kind = AnchorPathKind::linear;
  sphere.path.velocity = {1.0, 0.0, 0.0};
  model.colliders.push_back(sphere);
  CameraDirector director(CameraChoice{}, 16.0 / 9.0);
  director.update(model, model.particle_rest_position, 2.0);  // the sphere is at (2, -2, 0)
  EXPECT_TRUE(all_visible(director.camera(), model.particle_rest_position));
  EXPECT_TRUE(all_visible(director.camera(), {Vec3{2.5, -2.5, 0.0}, Vec3{1.5, -1.5, 0.0}, Vec3{2.0, -2.0, 0.5}}));
  EXPECT_LT(director.ground_height(), -2.5);
  EXPECT_GT(director.ground_height(), -10.0) << "the floor plane does not stretch the framing";
}

}  // namespace
}  // namespace clothsim::render
