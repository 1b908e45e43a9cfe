// Picking and dragging geometry (apps/clothsim/viewer/interaction.h) on the renderer's Camera:
// a particle is picked where it appears on screen, within a pixel radius, the nearer one winning
// a tie; a dragged particle's target lies under the cursor, on the plane facing the camera.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "viewer/interaction.h"

namespace clothsim::viewer {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;

render::Camera test_camera() {
  render::Camera camera;
  camera.target = {0.0, 0.0, 0.0};
  camera.azimuth = 0.4;
  camera.elevation = 0.6;
  camera.distance = 12.0;
  return camera;
}

std::vector<Vec3> grid(int rows, int cols) {
  std::vector<Vec3> points;
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) points.push_back({j - (cols - 1) / 2.0, 0.0, i - (rows - 1) / 2.0});
  }
  return points;
}

TEST(Picking, TheParticleUnderTheCursorIsPicked) {
  const render::Camera camera = test_camera();
  const std::vector<Vec3> points = grid(5, 5);
  for (std::size_t p = 0; p < points.size(); ++p) {
    const render::Projection at = camera.project(points[p], kWidth, kHeight);
    ASSERT_TRUE(at.visible);
    EXPECT_EQ(pick_particle(camera, points, at.x, at.y, kWidth, kHeight, 8.0), static_cast<long>(p));
    // A few pixels off still picks it; farther than the radius picks nothing nearby.
    EXPECT_EQ(pick_particle(camera, points, at.x + 3.0, at.y - 2.0, kWidth, kHeight, 8.0), static_cast<long>(p));
  }
  EXPECT_EQ(pick_particle(camera, points, 2.0, 2.0, kWidth, kHeight, 8.0), -1);  // empty corner of the view
}

TEST(Picking, OfTwoParticlesOnOneRayTheNearerWins) {
  const render::Camera camera = test_camera();
  const Vec3 near = camera.eye() + 4.0 * camera.forward();
  const Vec3 far = camera.eye() + 9.0 * camera.forward();
  const std::vector<Vec3> points = {far, near};
  EXPECT_EQ(pick_particle(camera, points, kWidth / 2.0, kHeight / 2.0, kWidth, kHeight, 5.0), 1);
  // Behind the eye is never picked.
  const std::vector<Vec3> behind = {camera.eye() - 3.0 * camera.forward()};
  EXPECT_EQ(pick_particle(camera, behind, kWidth / 2.0, kHeight / 2.0, kWidth, kHeight, 1e6), -1);
}

TEST(Dragging, TheTargetIsUnderTheCursorOnThePlaneFacingTheCamera) {
  const render::Camera camera = test_camera();
  const Vec3 grabbed{1.0, 0.5, -1.0};
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{{100.5, 80.5}, {320.0, 240.0}, {600.0, 400.0}}) {
    const std::optional<Vec3> target = drag_target(camera, grabbed, x, y, kWidth, kHeight);
    ASSERT_TRUE(target.has_value());
    EXPECT_NEAR(dot(*target - grabbed, camera.forward()), 0.0, 1e-9);  // same depth as the grab
    const render::Projection at = camera.project(*target, kWidth, kHeight);
    EXPECT_NEAR(at.x, x, 1e-6);
    EXPECT_NEAR(at.y, y, 1e-6);
  }
  // Grabbing a particle where it is leaves it there.
  const render::Projection here = camera.project(grabbed, kWidth, kHeight);
  const std::optional<Vec3> same = drag_target(camera, grabbed, here.x, here.y, kWidth, kHeight);
  ASSERT_TRUE(same.has_value());
  EXPECT_LT(norm(*same - grabbed), 1e-9);
}

}  // namespace
}  // namespace clothsim::viewer
