#include "core/closest_points.h"

#include <algorithm>

#include "core/shared_text.h"

namespace clothsim {

namespace {
namespace shared {
using Real = double;
#include "core/closest_points.inc"
}  // namespace shared
}  // namespace

TrianglePoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const shared::NearestOnTriangle nearest = shared::nearest_on_triangle(p, a, b, c);
  const TriangleFeature feature = nearest.feature == shared::kFeatureVertex ? TriangleFeature::vertex
                                  : nearest.feature == shared::kFeatureEdge ? TriangleFeature::edge
                                                                            : TriangleFeature::face;
  return {nearest.point, {nearest.weight.x, nearest.weight.y, nearest.weight.z}, feature, nearest.index};
}

SegmentPoints closest_points_of_segments(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2) {
  // Squared lengths below this are points: the division by them would amplify rounding.
  constexpr double kDegenerate = 1e-30;
  const Vec3 d1 = q1 - p1;
  const Vec3 d2 = q2 - p2;
  const Vec3 r = p1 - p2;
  const double a = dot(d1, d1);
  const double e = dot(d2, d2);
  const double f = dot(d2, r);
  double s = 0.0;
  double t = 0.0;
  if (a <= kDegenerate && e <= kDegenerate) {
    // Both points.
  } else if (a <= kDegenerate) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = dot(d1, r);
    if (e <= kDegenerate) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = dot(d1, d2);
      const double denominator = a * e - b * b;  // >= 0; 0 for parallel segments
      s = denominator > 0.0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return {s, t, p1 + s * d1, p2 + t * d2};
}

}  // namespace clothsim
