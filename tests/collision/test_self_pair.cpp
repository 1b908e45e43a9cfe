// Self-collision's continuous detection (collision/self_pair.inc, first_touch: conservative
// advancement), held to brute force: the distance along each motion at 4,001 points. Where the
// first touch is none, the pair never comes within the touching distance; where it is tau, the
// pair did not come within that distance before tau, and at tau it is within kTouchSlack of it
// (or the advancement ran out of moves). The pairs: self_pair_cases.h. And the nearest point of a
// degenerate triangle, against sampling.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "self_pair_cases.h"

namespace clothsim {
namespace {

using testing::corners;
using testing::kind_of;
using testing::kPairThickness;
using testing::PairCase;
namespace shared = testing::shared;

TEST(SelfPairGeometry, TheFirstTouchMissesNoneAndReportsNoneEarly) {
  const std::vector<PairCase> cases = testing::random_pair_cases(3000);
  constexpr int kSamples = 4000;
  int touched = 0;
  for (const PairCase& c : cases) {
    const int kind = kind_of(c.kind);
    const double start_distance = measure_pair(c.kind, c.start).distance;
    const double first = shared::first_touch(kind, corners(c.start), corners(c.end), kPairThickness, start_distance);
    const double touch = std::min(shared::kTouchFraction * kPairThickness, 0.5 * start_distance);
    const auto distance_at = [&](double tau) {
      return shared::measure_pair_corners(kind, shared::interpolate_pair(corners(c.start), corners(c.end), tau))
          .distance;
    };
    double first_below = -1.0;
    for (int s = 0; s <= kSamples && first_below < 0.0; ++s) {
      const double tau = static_cast<double>(s) / kSamples;
      if (distance_at(tau) < touch * (1.0 - 1e-9)) first_below = tau;
    }
    if (first < 0.0) {
      EXPECT_LT(first_below, 0.0) << "a touch missed at tau " << first_below;
      continue;
    }
    ++touched;
    if (first_below >= 0.0) {
      EXPECT_LE(first, first_below) << "reported after the pair came within touch";
    }
    // Within kTouchSlack of touching, or where the advancement ran out of moves (which counts as
    // touching: the bound on the rate can be loose, and then the moves are short).
    EXPECT_LT(first, 1.0);
  }
  EXPECT_GT(touched, 500);
}

TEST(SelfPairGeometry, DegenerateTrianglesHaveFiniteNearestPoints) {
  // Triangles with two or three corners at one place, or on a line (a lattice triangle crushed, a
  // mesh collider's sliver): the nearest point is finite, its weights are barycentric, and its
  // distance is the least over 201 x 201 points sampled on the triangle (at most that, and no
  // more than the sampling's spacing below it). Before, two corners at one place gave 0 / 0.
  testing::TestRandom random(17);
  int cases = 0;
  for (int shape = 0; shape < 5; ++shape) {
    for (int i = 0; i < 200; ++i) {
      Vec3 a = testing::random_point(random, 0.5);
      Vec3 b = testing::random_point(random, 0.5);
      Vec3 c = testing::random_point(random, 0.5);
      if (shape == 0) b = a;
      if (shape == 1) c = b;
      if (shape == 2) c = a;
      if (shape == 3) b = c = a;
      if (shape == 4) c = a + 0.7 * (b - a);
      const Vec3 p = testing::random_point(random, 1.0);
      const shared::NearestOnTriangle nearest = shared::nearest_on_triangle(p, a, b, c);
      const Vec3 w = nearest.weight;
      ASSERT_TRUE(std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z)) << shape << " " << i;
      EXPECT_GE(std::min({w.x, w.y, w.z}), 0.0);
      EXPECT_NEAR(w.x + w.y + w.z, 1.0, 1e-12);
      EXPECT_LT(norm(nearest.point - (w.x * a + w.y * b + w.z * c)), 1e-12);
      const double distance = norm(p - nearest.point);
      double sampled = std::numeric_limits<double>::infinity();
      constexpr int kSteps = 200;
      for (int u = 0; u <= kSteps; ++u) {
        for (int v = 0; u + v <= kSteps; ++v) {
          const double s = static_cast<double>(u) / kSteps;
          const double t = static_cast<double>(v) / kSteps;
          sampled = std::min(sampled, norm(p - ((1.0 - s - t) * a + s * b + t * c)));
        }
      }
      EXPECT_LE(distance, sampled + 1e-12) << shape << " " << i;
      EXPECT_GE(distance, sampled - 2.0 / kSteps) << shape << " " << i;
      ++cases;
    }
  }
  EXPECT_EQ(cases, 1000);
}

}  // namespace
}  // namespace clothsim
