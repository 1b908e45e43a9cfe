// Picking and dragging geometry (apps/clothsim/viewer/interaction.h) on the renderer's Camera:
// a particle is picked where it appears on screen, within a pixel radius, the nearer one winning
// a tie; a dragged particle's target lies under the cursor, on the plane facing the camera; a
// cut breaks the intact connectors its screen segment (or its rest-lattice segment) crosses.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "model/model_edits.h"
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

// A model with spheres of `radius` at `centres` (the lattice is irrelevant to picking spheres).
ClothModel spheres_at(std::initializer_list<Vec3> centres, double radius) {
  ClothModel model;
  for (const Vec3& centre : centres) {
    Collider sphere;
    sphere.shape = ColliderShape::sphere;
    sphere.center = centre;
    sphere.radius = radius;
    add_collider(model, sphere);
  }
  return model;
}

TEST(Picking, TheSphereTheRayEntersFirstIsPickedWhereItIsNow) {
  const render::Camera camera = test_camera();
  const Vec3 near = camera.eye() + 4.0 * camera.forward();
  const Vec3 far = camera.eye() + 9.0 * camera.forward();
  ClothModel model = spheres_at({far, near, {40.0, 0.0, 0.0}}, 0.5);
  const std::optional<SphereHit> hit = pick_sphere(camera, model, 0.0, kWidth / 2.0, kHeight / 2.0, kWidth, kHeight);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->collider, 1u);
  EXPECT_NEAR(hit->distance, 3.5, 1e-9);                                                 // where the ray enters it
  EXPECT_FALSE(pick_sphere(camera, model, 0.0, 2.0, 2.0, kWidth, kHeight).has_value());  // an empty corner

  // Moved by the hand (2 m along the camera's right by t = 1 s), it is picked where it is then.
  drive_collider(model, 1, 2.0 * camera.right(), 0.0, 1.0);
  const render::Projection moved = camera.project(near + 2.0 * camera.right(), kWidth, kHeight);
  const std::optional<SphereHit> moved_hit = pick_sphere(camera, model, 1.0, moved.x, moved.y, kWidth, kHeight);
  ASSERT_TRUE(moved_hit.has_value());
  EXPECT_EQ(moved_hit->collider, 1u);
  EXPECT_EQ(pick_sphere(camera, model, 1.0, kWidth / 2.0, kHeight / 2.0, kWidth, kHeight)->collider, 0u);
}

TEST(Picking, ANewSphereStartsClearOfTheSheetInView) {
  const render::Camera camera = test_camera();
  const std::vector<Vec3> points = grid(5, 5);  // a 4 x 4 square around the origin
  const double radius = 0.8;
  const Vec3 centre = place_beside_sheet(camera, points, radius);
  for (const Vec3& p : points) EXPECT_GT(norm(p - centre), radius);
  EXPECT_TRUE(camera.project(centre, kWidth, kHeight).visible);
  EXPECT_GT(dot(centre, camera.right()), 0.0);  // on the right of the sheet
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

// The connectors from row `row` south to row `row` + 1, ascending.
std::vector<std::uint32_t> south_connectors(const ClothModel& model, int row) {
  std::vector<std::uint32_t> connectors;
  for (std::uint32_t e = 0; e < model.connector_count(); ++e) {
    const auto [a, b] = model.connector_particles[e];
    if (static_cast<int>(a) / model.cols == row && b == a + static_cast<std::uint32_t>(model.cols)) {
      connectors.push_back(e);
    }
  }
  return connectors;
}

TEST(Cutting, AScreenSegmentCutsTheConnectorsItCrosses) {
  const render::Camera camera = test_camera();
  ClothModel model = build_lattice(LatticeDef{.rows = 5, .cols = 5, .spacing = 1.0}, Environment{}, {});
  const std::vector<Vec3>& points = model.particle_rest_position;  // rows at z = -2 .. 2
  // A segment drawn on the screen over the line z = 0.5, across the whole sheet: between rows 2
  // and 3.
  const render::Projection from = camera.project({-3.0, 0.0, 0.5}, kWidth, kHeight);
  const render::Projection to = camera.project({3.0, 0.0, 0.5}, kWidth, kHeight);
  const std::vector<std::uint32_t> expected = south_connectors(model, 2);
  ASSERT_EQ(expected.size(), 5u);
  EXPECT_EQ(connectors_crossed_on_screen(camera, model, points, from.x, from.y, to.x, to.y, kWidth, kHeight), expected);
  // The same cut in rest-lattice coordinates.
  EXPECT_EQ(connectors_crossed_in_lattice(model, {2.5, -1.0}, {2.5, 5.0}), expected);
  // Half way across: the connectors of columns 0..2 only.
  EXPECT_EQ(connectors_crossed_in_lattice(model, {2.5, -1.0}, {2.5, 2.2}),
            (std::vector<std::uint32_t>{expected[0], expected[1], expected[2]}));
  // A broken connector is not cut again; a segment off the sheet cuts nothing.
  ASSERT_TRUE(break_connector(model, expected[1]));
  EXPECT_EQ(connectors_crossed_in_lattice(model, {2.5, -1.0}, {2.5, 2.2}),
            (std::vector<std::uint32_t>{expected[0], expected[2]}));
  EXPECT_TRUE(connectors_crossed_in_lattice(model, {-1.0, -1.0}, {-1.0, 9.0}).empty());
  EXPECT_TRUE(connectors_crossed_on_screen(camera, model, points, 1.0, 1.0, 5.0, 3.0, kWidth, kHeight).empty());
}

}  // namespace
}  // namespace clothsim::viewer
