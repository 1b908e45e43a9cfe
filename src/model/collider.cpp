#include "model/collider.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include "core/assert.h"
#include "core/shared_text.h"

namespace clothsim {
namespace {

// The analytic shapes' distances, the text the device's obstacle pass compiles as well.
namespace shapes {
using Real = double;
using std::abs;
using std::clamp;
using std::max;
#include "model/collider_shapes.inc"
}  // namespace shapes

SurfaceDistance surface(const shapes::ShapeDistance& shape) { return {shape.distance, shape.normal, {}}; }

Vec3 unit_or_zero(const Vec3& v) {
  const double length = norm(v);
  return length > 0.0 ? v / length : Vec3{};
}

void assert_prepared(const TriangleMesh& mesh) {
  CLOTHSIM_ASSERT(mesh.triangle_normal.size() == mesh.triangle.size() &&
                      mesh.edge_pseudonormal.size() == 3 * mesh.triangle.size() &&
                      mesh.vertex_pseudonormal.size() == mesh.vertex.size() &&
                      mesh.node_triangle.size() == mesh.triangle.size() && !mesh.node_low.empty(),
                  "mesh collider not prepared (prepare_triangle_mesh)");
}

// The mesh distance, the text the device's obstacle pass compiles as well, on the TriangleMesh's
// arrays.
namespace shapes {
using uint = std::uint32_t;
using std::clamp;
using std::sqrt;
inline constexpr double kNoSurface = std::numeric_limits<double>::infinity();
inline constexpr double kRealEpsilon = std::numeric_limits<double>::epsilon();
#include "core/closest_points.inc"
struct MeshView {
  const TriangleMesh* mesh;
};
inline Vec3 mesh_vertex(const MeshView& m, uint v) { return m.mesh->vertex[v]; }
inline uint mesh_corner(const MeshView& m, uint t, uint k) { return m.mesh->triangle[t][k]; }
inline Vec3 mesh_triangle_normal(const MeshView& m, uint t) { return m.mesh->triangle_normal[t]; }
inline Vec3 mesh_vertex_pseudonormal(const MeshView& m, uint v) { return m.mesh->vertex_pseudonormal[v]; }
inline Vec3 mesh_edge_pseudonormal(const MeshView& m, uint t, uint k) { return m.mesh->edge_pseudonormal[3 * t + k]; }
inline Vec3 mesh_node_low(const MeshView& m, uint node) { return m.mesh->node_low[node]; }
inline Vec3 mesh_node_high(const MeshView& m, uint node) { return m.mesh->node_high[node]; }
inline uint mesh_node_child(const MeshView& m, uint node) { return m.mesh->node_child[node]; }
inline uint mesh_node_first(const MeshView& m, uint node) { return m.mesh->node_first[node]; }
inline uint mesh_node_count(const MeshView& m, uint node) { return m.mesh->node_count[node]; }
inline uint mesh_node_triangle(const MeshView& m, uint k) { return m.mesh->node_triangle[k]; }
inline uint mesh_triangle_count(const MeshView& m) { return static_cast<uint>(m.mesh->triangle.size()); }
#include "model/mesh_distance.inc"
}  // namespace shapes

// Builds the subtree of node `node` over node_triangle[first, first + count).
void build_node(TriangleMesh& mesh, const std::vector<Vec3>& centroid, std::uint32_t node, std::uint32_t first,
                std::uint32_t count) {
  const double inf = std::numeric_limits<double>::infinity();
  Vec3 low{inf, inf, inf}, high{-inf, -inf, -inf};
  Vec3 centre_low = low, centre_high = high;
  const auto grow = [](Vec3& lo, Vec3& hi, const Vec3& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  };
  for (std::uint32_t k = first; k < first + count; ++k) {
    const std::uint32_t t = mesh.node_triangle[k];
    for (std::uint32_t corner : mesh.triangle[t]) grow(low, high, mesh.vertex[corner]);
    grow(centre_low, centre_high, centroid[t]);
  }
  mesh.node_low[node] = low;
  mesh.node_high[node] = high;
  if (count <= kMeshLeafSize) {
    mesh.node_first[node] = first;
    mesh.node_count[node] = count;
    return;
  }
  const Vec3 spread = centre_high - centre_low;
  const int axis = spread.x >= spread.y && spread.x >= spread.z ? 0 : (spread.y >= spread.z ? 1 : 2);
  const auto begin = mesh.node_triangle.begin() + first;
  const auto middle = begin + count / 2;
  std::nth_element(begin, middle, begin + count,
                   [&](std::uint32_t i, std::uint32_t j) { return centroid[i][axis] < centroid[j][axis]; });
  const auto left = static_cast<std::uint32_t>(mesh.node_low.size());
  for (int k = 0; k < 2; ++k) {
    mesh.node_low.emplace_back();
    mesh.node_high.emplace_back();
    mesh.node_child.push_back(0);
    mesh.node_first.push_back(0);
    mesh.node_count.push_back(0);
  }
  mesh.node_child[node] = left;
  mesh.node_count[node] = 0;
  build_node(mesh, centroid, left, first, count / 2);
  build_node(mesh, centroid, left + 1, first + count / 2, count - count / 2);
}

}  // namespace

SurfaceDistance mesh_distance_brute_force(const TriangleMesh& mesh, const Vec3& x) {
  assert_prepared(mesh);
  const shapes::MeshView view{&mesh};
  shapes::NearestTriangle nearest = shapes::no_triangle_yet();
  for (std::size_t t = 0; t < mesh.triangle.size(); ++t) {
    shapes::visit_triangle(view, static_cast<std::uint32_t>(t), x, nearest);
  }
  return surface(shapes::signed_from_nearest(nearest, x));
}

void prepare_triangle_mesh(TriangleMesh& mesh) {
  const std::size_t triangle_count = mesh.triangle.size();
  mesh.triangle_normal.assign(triangle_count, Vec3{});
  mesh.vertex_pseudonormal.assign(mesh.vertex.size(), Vec3{});
  mesh.edge_pseudonormal.assign(3 * triangle_count, Vec3{});
  // Sum of the face normals at each undirected edge (smaller vertex index first).
  std::map<std::pair<std::uint32_t, std::uint32_t>, Vec3> edge_sum;
  const auto edge_key = [](std::uint32_t i, std::uint32_t j) { return std::pair{std::min(i, j), std::max(i, j)}; };
  for (std::size_t t = 0; t < triangle_count; ++t) {
    const auto& corner = mesh.triangle[t];
    for (std::uint32_t index : corner) {
      CLOTHSIM_ASSERT(index < mesh.vertex.size(), "mesh triangle corner out of range");
    }
    const Vec3 normal = unit_or_zero(
        cross(mesh.vertex[corner[1]] - mesh.vertex[corner[0]], mesh.vertex[corner[2]] - mesh.vertex[corner[0]]));
    mesh.triangle_normal[t] = normal;
    for (int k = 0; k < 3; ++k) {
      const Vec3& here = mesh.vertex[corner[k]];
      const Vec3 to_next = unit_or_zero(mesh.vertex[corner[(k + 1) % 3]] - here);
      const Vec3 to_previous = unit_or_zero(mesh.vertex[corner[(k + 2) % 3]] - here);
      const double angle = std::acos(std::clamp(dot(to_next, to_previous), -1.0, 1.0));
      mesh.vertex_pseudonormal[corner[k]] += angle * normal;
      edge_sum[edge_key(corner[k], corner[(k + 1) % 3])] += normal;
    }
  }
  for (Vec3& normal : mesh.vertex_pseudonormal) normal = unit_or_zero(normal);
  for (std::size_t t = 0; t < triangle_count; ++t) {
    const auto& corner = mesh.triangle[t];
    for (int k = 0; k < 3; ++k) {
      mesh.edge_pseudonormal[3 * t + k] = unit_or_zero(edge_sum[edge_key(corner[k], corner[(k + 1) % 3])]);
    }
  }
  // The hierarchy: the root over every triangle, children appended as they are made.
  std::vector<Vec3> centroid(triangle_count);
  for (std::size_t t = 0; t < triangle_count; ++t) {
    const auto& corner = mesh.triangle[t];
    centroid[t] = (mesh.vertex[corner[0]] + mesh.vertex[corner[1]] + mesh.vertex[corner[2]]) / 3.0;
  }
  mesh.node_triangle.resize(triangle_count);
  for (std::size_t t = 0; t < triangle_count; ++t) mesh.node_triangle[t] = static_cast<std::uint32_t>(t);
  mesh.node_low.assign(1, Vec3{});
  mesh.node_high.assign(1, Vec3{});
  mesh.node_child.assign(1, 0);
  mesh.node_first.assign(1, 0);
  mesh.node_count.assign(1, 0);
  build_node(mesh, centroid, 0, 0, static_cast<std::uint32_t>(triangle_count));
}

SurfaceDistance signed_distance(const Collider& collider, const Vec3& x, double time) {
  // The shape moves rigidly: query the point in the shape's frame at t = 0.
  const Vec3 shift = collider.path.position(time) - collider.path.position(0.0);
  const Vec3 local = x - shift;
  SurfaceDistance out;
  switch (collider.shape) {
    case ColliderShape::plane: out = surface(shapes::plane_distance(collider.point, collider.normal, local)); break;
    case ColliderShape::sphere: out = surface(shapes::sphere_distance(collider.center, collider.radius, local)); break;
    case ColliderShape::box: out = surface(shapes::box_distance(collider.center, collider.half_extents, local)); break;
    case ColliderShape::capsule:
      out = surface(shapes::capsule_distance(collider.a, collider.b, collider.radius, local));
      break;
    case ColliderShape::mesh: {
      CLOTHSIM_ASSERT(collider.mesh != nullptr, "mesh collider without a mesh");
      assert_prepared(*collider.mesh);
      const shapes::MeshView view{collider.mesh.get()};
      out = surface(shapes::signed_from_nearest(shapes::nearest_triangle(view, local), local));
      break;
    }
  }
  out.velocity = collider.path.velocity_at(time);
  return out;
}

}  // namespace clothsim
