// Tests of render/camera: projection of known points against hand-computed pixels, the view
// matrix, framing (every point inside the image; fit() tight), pick rays through particles,
// and orbit/pan/zoom behaving as the viewer expects. No OpenGL needed.
#include "render/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "model/cloth_model.h"

namespace clothsim::render {
namespace {

constexpr double kPi = 3.14159265358979323846;

void expect_near(const Vec3& actual, const Vec3& expected, double tolerance) {
  EXPECT_NEAR(actual.x, expected.x, tolerance);
  EXPECT_NEAR(actual.y, expected.y, tolerance);
  EXPECT_NEAR(actual.z, expected.z, tolerance);
}

// Looking from +z at the origin from 10 m, 90 degree field of view: the visible half-height at
// the target is 10 m.
Camera front_camera() {
  Camera camera;
  camera.target = {0.0, 0.0, 0.0};
  camera.azimuth = 0.0;
  camera.elevation = 0.0;
  camera.distance = 10.0;
  camera.field_of_view = kPi / 2.0;
  return camera;
}

TEST(Camera, EyeAndViewMatrix) {
  const Camera camera = front_camera();
  expect_near(camera.eye(), {0.0, 0.0, 10.0}, 1e-12);
  expect_near(camera.forward(), {0.0, 0.0, -1.0}, 1e-12);
  expect_near(camera.right(), {1.0, 0.0, 0.0}, 1e-12);
  expect_near(camera.up(), {0.0, 1.0, 0.0}, 1e-12);
  expect_near(transform_point(camera.view(), camera.eye()), {0.0, 0.0, 0.0}, 1e-12);
  expect_near(transform_point(camera.view(), camera.target), {0.0, 0.0, -10.0}, 1e-12);

  Camera side = camera;
  side.azimuth = kPi / 2.0;  // from +x
  expect_near(side.eye(), {10.0, 0.0, 0.0}, 1e-12);
  Camera above = camera;
  above.elevation = 1.0;
  EXPECT_NEAR(above.eye().y, 10.0 * std::sin(1.0), 1e-12);
  EXPECT_NEAR(norm(above.eye() - above.target), 10.0, 1e-12);
}

TEST(Camera, ProjectsKnownPointsToKnownPixels) {
  const Camera camera = front_camera();
  const Projection centre = camera.project({0.0, 0.0, 0.0}, 200, 100);
  EXPECT_TRUE(centre.visible);
  EXPECT_NEAR(centre.x, 100.0, 1e-9);
  EXPECT_NEAR(centre.y, 50.0, 1e-9);
  // Half-height 10 m at the target; aspect 2, so half-width 20 m. y runs down the image.
  const Projection up_right = camera.project({10.0, 5.0, 0.0}, 200, 100);
  EXPECT_NEAR(up_right.x, 150.0, 1e-9);
  EXPECT_NEAR(up_right.y, 25.0, 1e-9);
  // Perspective: twice as far, half the offset.
  const Projection far = camera.project({10.0, 5.0, -10.0}, 200, 100);
  EXPECT_NEAR(far.x, 125.0, 1e-9);
  EXPECT_NEAR(far.y, 37.5, 1e-9);
  EXPECT_FALSE(camera.project({0.0, 0.0, 11.0}, 200, 100).visible);  // behind the eye
  EXPECT_FALSE(camera.project({30.0, 0.0, 0.0}, 200, 100).visible);  // off to the right
  // Depth increases with distance.
  EXPECT_LT(centre.depth, far.depth);
}

std::vector<Vec3> random_cloud(unsigned seed) {
  std::mt19937 generator(seed);
  std::uniform_real_distribution<double> coordinate(-3.0, 3.0);
  std::vector<Vec3> points;
  for (int i = 0; i < 200; ++i) {
    points.push_back({coordinate(generator) + 5.0, 0.3 * coordinate(generator) - 2.0, coordinate(generator)});
  }
  return points;
}

TEST(Camera, FrameAndFitKeepEveryPointInView) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const std::vector<Vec3> points = random_cloud(seed);
    for (const double aspect : {0.5, 1.0, 16.0 / 9.0}) {
      const int height = 400;
      const int width = static_cast<int>(aspect * height);
      Camera framed;
      framed.azimuth = 0.3 * seed;
      framed.elevation = 0.2 * seed - 0.5;
      Camera fitted = framed;
      framed.frame(points, static_cast<double>(width) / height);
      fitted.fit(points, static_cast<double>(width) / height);
      EXPECT_LE(fitted.distance, framed.distance * (1.0 + 1e-9)) << "fit is at least as tight as the sphere";
      double widest = 0.0;  // largest |ndc| over the points, fitted
      for (const Vec3& p : points) {
        const Projection a = framed.project(p, width, height);
        const Projection b = fitted.project(p, width, height);
        EXPECT_TRUE(a.visible);
        EXPECT_TRUE(b.visible);
        widest = std::max({widest, std::abs(2.0 * b.x / width - 1.0), std::abs(2.0 * b.y / height - 1.0)});
      }
      // Tight: some point is within the 5% margin of an edge.
      EXPECT_GT(widest, 0.9) << "seed " << seed << ", aspect " << aspect;
    }
  }
}

TEST(Camera, FrameIgnoresNonFinitePointsAndKeepsTheCameraWithoutPoints) {
  Camera camera = front_camera();
  const std::vector<Vec3> none = {{NAN, 0.0, 0.0}};
  camera.frame(none, 1.0);
  camera.fit(none, 1.0);
  EXPECT_EQ(camera.distance, 10.0);
  const std::vector<Vec3> points = {{1.0, 0.0, 0.0}, {-1.0, 0.0, 0.0}, {INFINITY, 0.0, 0.0}};
  camera.frame(points, 1.0);
  expect_near(camera.target, {0.0, 0.0, 0.0}, 1e-12);
  EXPECT_TRUE(std::isfinite(camera.distance));
  // A sphere of radius 1.1 just fits a 90 degree view at distance 1.1 / sin(45 degrees).
  EXPECT_NEAR(camera.distance, 1.1 / std::sin(kPi / 4.0), 1e-9);
}

TEST(Camera, PickRayHitsTheParticleUnderThePixel) {
  const ClothModel model = build_lattice(LatticeDef{.rows = 9, .cols = 13, .spacing = 0.25}, Environment{}, {});
  std::vector<Vec3> position = model.particle_rest_position;
  for (Vec3& p : position) p.y = 0.2 * std::sin(3.0 * p.x) * std::cos(2.0 * p.z);
  Camera camera;
  camera.azimuth = 0.8;
  camera.elevation = 0.6;
  camera.fit(position, 4.0 / 3.0);
  const int width = 640;
  const int height = 480;
  for (const std::size_t particle : {std::size_t{0}, std::size_t{12}, std::size_t{58}, std::size_t{116}}) {
    const Projection at = camera.project(position[particle], width, height);
    ASSERT_TRUE(at.visible);
    const Ray ray = camera.pick_ray(at.x, at.y, width, height);
    EXPECT_NEAR(norm(ray.direction), 1.0, 1e-12);
    expect_near(ray.origin, camera.eye(), 1e-12);
    // The ray passes through the particle.
    const Vec3 relative = position[particle] - ray.origin;
    EXPECT_NEAR(norm(relative - dot(relative, ray.direction) * ray.direction), 0.0, 1e-9);
    EXPECT_EQ(pick_nearest_point(ray, position, 0.1), static_cast<long>(particle));
    // Three pixels off still picks it: the spacing is many pixels wide here.
    EXPECT_EQ(pick_nearest_point(camera.pick_ray(at.x + 3.0, at.y - 2.0, width, height), position, 0.1),
              static_cast<long>(particle));
  }
  // Far off the sheet: nothing.
  EXPECT_EQ(pick_nearest_point(camera.pick_ray(1.0, 1.0, width, height), position, 0.05), -1);
}

TEST(Camera, PickPrefersTheNearerOfTwoPointsOnTheRay) {
  const Camera camera = front_camera();
  const std::vector<Vec3> points = {{0.0, 0.0, -5.0}, {0.0, 0.0, 5.0}, {0.0, 0.0, 20.0}};  // last: behind the eye
  EXPECT_EQ(pick_nearest_point(camera.pick_ray(50.0, 50.0, 100, 100), points, 0.5), 1);
}

TEST(Camera, OrbitPanZoom) {
  Camera camera = front_camera();
  camera.orbit(0.0, 10.0);
  EXPECT_DOUBLE_EQ(camera.elevation, Camera::kMaxElevation);
  camera.orbit(0.0, -20.0);
  EXPECT_DOUBLE_EQ(camera.elevation, -Camera::kMaxElevation);
  camera.orbit(4.0 * kPi + 0.5, 0.0);
  EXPECT_NEAR(camera.azimuth, 0.5, 1e-12);

  // Pan: the old target moves right by a quarter of the height and up by a tenth.
  Camera panned = front_camera();
  panned.pan(0.25, 0.1);
  const Projection old_target = panned.project({0.0, 0.0, 0.0}, 100, 100);
  EXPECT_NEAR(old_target.x, 50.0 + 25.0, 1e-9);
  EXPECT_NEAR(old_target.y, 50.0 - 10.0, 1e-9);
  EXPECT_NEAR(panned.distance, 10.0, 1e-12);

  Camera zoomed = front_camera();
  zoomed.zoom(0.5);
  EXPECT_DOUBLE_EQ(zoomed.distance, 5.0);
  zoomed.zoom(-1.0);  // ignored
  zoomed.zoom(NAN);
  EXPECT_DOUBLE_EQ(zoomed.distance, 5.0);
  zoomed.zoom(1e-12);
  EXPECT_DOUBLE_EQ(zoomed.distance, 1e-4);
}

}  // namespace
}  // namespace clothsim::render
