#include "model/collider.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/assert.h"

namespace clothsim {
namespace {

SurfaceDistance plane_distance(const Collider& c, const Vec3& x) {
  return {dot(x - c.point, c.normal), c.normal, {}};
}

// Towards the centre's opposite side when x is at the centre (any direction is nearest; up is
// the one a falling sheet expects).
SurfaceDistance sphere_distance(const Vec3& center, double radius, const Vec3& x) {
  const Vec3 offset = x - center;
  const double length = norm(offset);
  const Vec3 normal = length > 0.0 ? offset / length : Vec3{0.0, 1.0, 0.0};
  return {length - radius, normal, {}};
}

SurfaceDistance box_distance(const Collider& c, const Vec3& x) {
  const Vec3 local = x - c.center;
  const std::array<double, 3> p = {local.x, local.y, local.z};
  const std::array<double, 3> h = {c.half_extents.x, c.half_extents.y, c.half_extents.z};
  std::array<double, 3> q{};  // |p| - h per axis: > 0 outside that slab
  for (int i = 0; i < 3; ++i) q[i] = std::abs(p[i]) - h[i];
  const double largest = std::max({q[0], q[1], q[2]});
  if (largest <= 0.0) {
    // Inside: the nearest face is the one with the largest (least negative) q.
    const int axis = q[0] == largest ? 0 : q[1] == largest ? 1 : 2;
    std::array<double, 3> n{};
    n[axis] = p[axis] >= 0.0 ? 1.0 : -1.0;
    return {largest, {n[0], n[1], n[2]}, {}};
  }
  // Outside: the vector from the nearest box point to x.
  std::array<double, 3> d{};
  for (int i = 0; i < 3; ++i) d[i] = q[i] > 0.0 ? std::copysign(q[i], p[i]) : 0.0;
  const Vec3 outside{d[0], d[1], d[2]};
  const double length = norm(outside);
  return {length, outside / length, {}};
}

SurfaceDistance capsule_distance(const Collider& c, const Vec3& x) {
  const Vec3 axis = c.b - c.a;
  const double axis_squared = dot(axis, axis);
  const double s = axis_squared > 0.0 ? std::clamp(dot(x - c.a, axis) / axis_squared, 0.0, 1.0) : 0.0;
  return sphere_distance(c.a + s * axis, c.radius, x);
}

}  // namespace

SurfaceDistance signed_distance(const Collider& collider, const Vec3& x, double time) {
  // The shape moves rigidly: query the point in the shape's frame at t = 0.
  const Vec3 shift = collider.path.position(time) - collider.path.position(0.0);
  const Vec3 local = x - shift;
  SurfaceDistance out;
  switch (collider.shape) {
    case ColliderShape::plane:
      out = plane_distance(collider, local);
      break;
    case ColliderShape::sphere:
      out = sphere_distance(collider.center, collider.radius, local);
      break;
    case ColliderShape::box:
      out = box_distance(collider, local);
      break;
    case ColliderShape::capsule:
      out = capsule_distance(collider, local);
      break;
    case ColliderShape::mesh:
      CLOTHSIM_ASSERT(false, "mesh colliders are not implemented yet");
      break;
  }
  out.velocity = collider.path.velocity_at(time);
  return out;
}

}  // namespace clothsim
