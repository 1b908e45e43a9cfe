// The colliders on the device, as the obstacle passes query them: each collider's row of
// `colliders` (device_step.h, kColliderReals), its motion over the advance (path_motion.glsl), its
// signed distance (model/collider_shapes.inc; a mesh's through its hierarchy, model/mesh_distance.inc),
// and the contact law the CPU runs (collision/obstacle_contact.inc). The includer declares
// `colliders`, `mesh_reals` and `mesh_uints`.
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
#include "core/closest_points.inc"

// A mesh collider's arrays in `mesh_reals` and `mesh_uints` (device_step.h, kMeshHeaderUints).
struct MeshView {
  uint reals;  // where its Reals start
  uint uints;  // where its words start
  uint vertices;
  uint triangles;
  uint nodes;
};

MeshView mesh_of(uint c) {
  const uint h = kMeshHeaderUints * c;
  return MeshView(mesh_uints[h], mesh_uints[h + 1u], mesh_uints[h + 2u], mesh_uints[h + 3u], mesh_uints[h + 4u]);
}

Vec3 mesh_vector(uint at) { return Vec3(mesh_reals[at], mesh_reals[at + 1u], mesh_reals[at + 2u]); }
Vec3 mesh_vertex(MeshView m, uint v) { return mesh_vector(m.reals + 3u * v); }
Vec3 mesh_vertex_pseudonormal(MeshView m, uint v) { return mesh_vector(m.reals + 3u * (m.vertices + v)); }
Vec3 mesh_triangle_normal(MeshView m, uint t) { return mesh_vector(m.reals + 6u * m.vertices + 3u * t); }
Vec3 mesh_edge_pseudonormal(MeshView m, uint t, uint k) {
  return mesh_vector(m.reals + 6u * m.vertices + 3u * m.triangles + 9u * t + 3u * k);
}
Vec3 mesh_node_low(MeshView m, uint node) { return mesh_vector(m.reals + 6u * m.vertices + 12u * m.triangles + 3u * node); }
Vec3 mesh_node_high(MeshView m, uint node) {
  return mesh_vector(m.reals + 6u * m.vertices + 12u * m.triangles + 3u * (m.nodes + node));
}
uint mesh_corner(MeshView m, uint t, uint k) { return mesh_uints[m.uints + 3u * t + k]; }
uint mesh_node_child(MeshView m, uint node) { return mesh_uints[m.uints + 3u * m.triangles + node]; }
uint mesh_node_first(MeshView m, uint node) { return mesh_uints[m.uints + 3u * m.triangles + m.nodes + node]; }
uint mesh_node_count(MeshView m, uint node) { return mesh_uints[m.uints + 3u * m.triangles + 2u * m.nodes + node]; }
uint mesh_node_triangle(MeshView m, uint k) { return mesh_uints[m.uints + 3u * m.triangles + 3u * m.nodes + k]; }
uint mesh_triangle_count(MeshView m) { return m.triangles; }

// An empty mesh's distance: far beyond any scene, within float's range.
const Real kNoSurface = Real(1e30);
#if CLOTHSIM_FLOAT64
const Real kRealEpsilon = Real(2.220446049250313e-16);  // 2^-52
#else
const Real kRealEpsilon = Real(1.1920928955078125e-7);  // 2^-23
#endif
#include "model/mesh_distance.inc"

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
  } else if (shape == kShapeCapsule) {
    d = capsule_distance(first, second, radius, local);
  } else {
    const MeshView mesh = mesh_of(obstacle.row / kColliderReals);
    d = signed_from_nearest(nearest_triangle(mesh, local), local);
  }
  return SurfaceDistance(d.distance, d.normal, obstacle.velocity);
}

#include "collision/obstacle_contact.inc"
