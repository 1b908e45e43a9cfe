// Obstacles the sheet collides with (docs/collisions.md): shapes, their motion, and their signed distance.
//
// A collider is a rigid shape that may move along a path of the kinds anchors have (fixed,
// linear, sinusoid, keyframes; model/anchor.h): at time t the shape is translated by
// path.position(t) - path.position(0). Shapes are given in world coordinates at t = 0.
//
// Every query goes through one function, signed_distance(): the distance from a point to the
// shape's surface, negative inside, with the outward unit normal of the nearest surface point and
// the shape's velocity there. The collision stage (collision/) needs nothing else, so a new
// shape is one more case here. Distances are exact (not bounds) for every shape:
//   plane    d = (x - point) . n                          (a half-space: everything below is inside)
//   sphere   d = |x - centre| - r
//   box      the exact box distance (outside: distance to the nearest face, edge or corner;
//            inside: minus the distance to the nearest face)
//   capsule  d = distance to the segment ab - r
//   mesh     distance to the nearest triangle, signed by the angle-weighted pseudonormal of the
//            nearest feature (Baerentzen and Aanaes 2005), which is exact for a closed,
//            consistently wound mesh. An open mesh (a table top alone) gets the same rule, so a
//            point behind its faces is inside at any distance; the collision stage limits how
//            deep that matters. The nearest triangle is found through a bounding-box hierarchy
//            (TriangleMesh::node_*), O(log n) per query for points near the surface.
// Rejected: sampled distance fields (grids). They blur edges and corners by a cell, and a table's
// edge is exactly where a tablecloth folds.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/vec3.h"
#include "model/anchor.h"

namespace clothsim {

enum class ColliderShape : std::uint8_t { plane, sphere, box, capsule, mesh };

// A triangle mesh, already scaled and translated into world coordinates.
//
// The pseudonormals sign mesh distances (Baerentzen and Aanaes 2005): the sign of a point is that
// of (x - c) . n where c is the nearest surface point and n the angle-weighted pseudonormal of the
// feature c lies on (face: its normal; edge: the sum of its two faces' normals; vertex: the sum of
// its faces' normals weighted by their angles at the vertex). Unlike the nearest face's normal,
// this is correct near edges and corners of closed meshes.
//
// The hierarchy is a binary tree of axis-aligned boxes over the triangles, split at the median
// centroid along the longest axis, at most kMeshLeafSize triangles per leaf; a query descends into
// the nearer child first and skips boxes farther than the best triangle so far. Rejected: a
// uniform grid (its cell size suits one triangle size, and a scanned mesh mixes many).
//
// prepare_triangle_mesh() fills the normals and the hierarchy from `vertex` and `triangle`; the
// mesh reader calls it once, and signed_distance() asserts it has been called.
struct TriangleMesh {
  std::vector<Vec3> vertex;                            // m
  std::vector<std::array<std::uint32_t, 3>> triangle;  // counter-clockwise seen from outside
  std::vector<Vec3> triangle_normal;                   // [triangle count], unit (zero if degenerate)
  std::vector<Vec3> vertex_pseudonormal;               // [vertex count], unit
  // [3 per triangle]: edge k of triangle t runs from corner k to corner (k + 1) % 3; unit. A
  // boundary edge (one face) takes that face's normal.
  std::vector<Vec3> edge_pseudonormal;
  // Hierarchy nodes, root first, [node count]: box corners (m); an inner node's children are
  // node_child and node_child + 1; a leaf (node_count > 0) holds the triangles
  // node_triangle[node_first .. node_first + node_count).
  std::vector<Vec3> node_low, node_high;
  std::vector<std::uint32_t> node_child, node_first, node_count;
  std::vector<std::uint32_t> node_triangle;  // [triangle count]: triangle indices in leaf order
};

inline constexpr std::uint32_t kMeshLeafSize = 4;

// Fills triangle_normal, the pseudonormals and the hierarchy from vertex and triangle.
void prepare_triangle_mesh(TriangleMesh& mesh);

struct Collider {
  ColliderShape shape = ColliderShape::plane;
  Vec3 point{0.0, 0.0, 0.0};                 // plane: a point on it, m
  Vec3 normal{0.0, 1.0, 0.0};                // plane: outward unit normal
  Vec3 center;                               // sphere, box: centre, m
  double radius = 0.0;                       // sphere, capsule: m
  Vec3 half_extents;                         // box: half sizes along x, y, z, m (axis-aligned)
  Vec3 a, b;                                 // capsule: the segment's ends, m
  std::shared_ptr<const TriangleMesh> mesh;  // mesh: shared, never changed after loading
  std::string mesh_file;                     // mesh: the file it was read from (for messages and output)
  double friction = -1.0;                    // Coulomb coefficient; < 0: the scene's collision.friction default
  AnchorPath path;                           // motion (fixed by default)
};

// Collision settings of a scene (scene keys collision.*).
struct CollisionSettings {
  double thickness = 0.005;  // m: particles stay this far outside every obstacle, and the sheet from itself
  bool self = false;         // self-collision on
  double friction = 0.3;     // Coulomb coefficient of cloth on cloth, and of obstacles without their own
};

// The Coulomb coefficient between the sheet and `collider`: its own, or the scene's default.
inline double collider_friction(const Collider& collider, const CollisionSettings& settings) {
  return collider.friction >= 0.0 ? collider.friction : settings.friction;
}

// The largest collision.thickness self-collision allows on a lattice of connector rest length
// `spacing` (exclusive): half of it. On the flat lattice the nearest pieces of sheet that share no
// particle are spacing / sqrt(2) apart (a particle and the diagonal of the quad beyond it), and a
// sheet in compression comes closer; half the spacing leaves that room, where a larger thickness
// would push the sheet's own neighbours apart at rest (collision/self_contacts.h).
inline double self_collision_thickness_limit(double spacing) { return 0.5 * spacing; }

// The nearest surface point's data for a query point.
struct SurfaceDistance {
  double distance = 0.0;  // m, negative inside
  Vec3 normal;            // outward unit normal at the nearest surface point
  Vec3 velocity;          // the shape's velocity (its path's), m/s
};

// Signed distance from `x` to `collider` at time `time` (s).
SurfaceDistance signed_distance(const Collider& collider, const Vec3& x, double time);

// How far the collider's shape is translated at `time` (s) from where it is given (its t = 0
// shape), m: the sphere's centre at `time` is collider.center + collider_offset(collider, time).
inline Vec3 collider_offset(const Collider& collider, double time) {
  return collider.path.position(time) - collider.path.position(0.0);
}

// The same distance as signed_distance() gives a mesh collider at rest, by visiting every
// triangle: the oracle the hierarchy is tested against.
SurfaceDistance mesh_distance_brute_force(const TriangleMesh& mesh, const Vec3& x);

}  // namespace clothsim
