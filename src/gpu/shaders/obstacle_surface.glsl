// The colliders on the device, as the obstacle passes query them: each collider's row of
// `colliders` (device_step.h, kColliderReals), its motion over the advance (path_motion.glsl), its
// signed distance (model/collider_shapes.inc), and the contact law the CPU runs
// (collision/obstacle_contact.inc). The includer declares `colliders`.
#include "gpu/shaders/path_motion.glsl"

struct SurfaceDistance {
  Real distance;  // m, negative inside
  Vec3 normal;    // outward unit normal of the nearest surface point
  Vec3 velocity;  // the collider's velocity, m/s
};

// A collider at one time: its row, and how far its shape has moved from where the row gives it.
struct ObstacleAtStepEnd {
  uint row;     // the first of its Reals in `colliders`
  Vec3 offset;  // m, collider_offset() at that time
  Vec3 velocity;
};

Vec3 collider_vector(uint row, uint slot) {
  return Vec3(colliders[row + slot], colliders[row + slot + 1u], colliders[row + slot + 2u]);
}

PathMotion collider_motion(uint c, Real tau) {
  const uint path = c * kColliderReals + kColliderPath;
  return path_motion(collider_vector(path, 0u), collider_vector(path, 3u), collider_vector(path, 6u),
                     colliders[path + 9u], colliders[path + 10u], tau);
}

Vec3 collider_offset(uint c, Real tau) { return collider_motion(c, tau).position; }

ObstacleAtStepEnd obstacle_at(uint c, Real tau) {
  const PathMotion motion = collider_motion(c, tau);
  ObstacleAtStepEnd obstacle;
  obstacle.row = c * kColliderReals;
  obstacle.offset = motion.position;
  obstacle.velocity = motion.velocity;
  return obstacle;
}

#include "model/collider_shapes.inc"

// The signed distance of x from the collider, queried in the shape's frame as given, as
// signed_distance() does on the CPU.
SurfaceDistance obstacle_surface(const ObstacleAtStepEnd obstacle, const Vec3 x) {
  const uint row = obstacle.row;
  const Vec3 local = x - obstacle.offset;
  const uint shape = uint(colliders[row + kColliderShape]);
  const Vec3 first = collider_vector(row, kColliderFirst);
  const Vec3 second = collider_vector(row, kColliderSecond);
  const Real radius = colliders[row + kColliderRadius];
  ShapeDistance d;
  if (shape == kShapePlane) {
    d = plane_distance(first, second, local);
  } else if (shape == kShapeSphere) {
    d = sphere_distance(first, radius, local);
  } else if (shape == kShapeBox) {
    d = box_distance(first, second, local);
  } else {
    d = capsule_distance(first, second, radius, local);
  }
  return SurfaceDistance(d.distance, d.normal, obstacle.velocity);
}

#include "collision/obstacle_contact.inc"
