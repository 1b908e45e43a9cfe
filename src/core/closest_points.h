// Closest points between a point and a triangle, and between two segments: the narrow phase of
// self-collision (collision/self_contacts.h). The point-triangle query is the shared text
// core/closest_points.inc, which the mesh colliders' distance (model/mesh_distance.inc) uses on
// the CPU and on the device.
//
// Both return the closest points as weights of the primitives' corners, so that a caller can
// move the corners (an impulse distributed by barycentric weights) as well as read the points.
// Algorithms: Ericson, Real-Time Collision Detection (2005), sections 5.1.5
// (ClosestPtPointTriangle, by Voronoi regions) and 5.1.9 (ClosestPtSegmentSegment).
#pragma once

#include <array>
#include <cstdint>

#include "core/vec3.h"

namespace clothsim {

// The feature of a triangle a point's nearest point lies on: corner k, edge k (corner k to corner
// (k + 1) % 3), or the face's interior.
enum class TriangleFeature : std::uint8_t { vertex, edge, face };

struct TrianglePoint {
  Vec3 point;                      // the nearest point of the triangle
  std::array<double, 3> weight{};  // barycentric: point = w0 a + w1 b + w2 c, each in [0, 1], sum 1
  TriangleFeature feature = TriangleFeature::face;
  int index = 0;  // corner or edge number
};

// Nearest point of triangle (a, b, c) to p. A degenerate triangle gives one of its nearest points.
TrianglePoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

struct SegmentPoints {
  double s = 0.0;  // on the first segment: p1 + s (q1 - p1), s in [0, 1]
  double t = 0.0;  // on the second: p2 + t (q2 - p2), t in [0, 1]
  Vec3 first;
  Vec3 second;
};

// Nearest points of segments p1-q1 and p2-q2. Parallel segments have a line of nearest pairs;
// the one returned has s = 0 where that is among them.
SegmentPoints closest_points_of_segments(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2);

}  // namespace clothsim
