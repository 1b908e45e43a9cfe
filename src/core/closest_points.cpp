#include "core/closest_points.h"

#include <algorithm>

#include "core/shared_text.h"

namespace clothsim {

namespace {
namespace shared {
using Real = double;
using std::clamp;
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
  const shared::NearestOnSegments nearest = shared::nearest_on_segments(p1, q1, p2, q2);
  return {nearest.s, nearest.t, nearest.first, nearest.second};
}

}  // namespace clothsim
