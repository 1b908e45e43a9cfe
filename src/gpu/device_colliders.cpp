#include "gpu/device_colliders.h"

#include <algorithm>
#include <array>
#include <cstddef>

#include "core/assert.h"
#include "gpu/device_paths.h"
#include "gpu/shaders/device_step.h"

namespace clothsim::gpu {

namespace {

double shape_code(ColliderShape shape) {
  switch (shape) {
    case ColliderShape::plane: return kShapePlane;
    case ColliderShape::sphere: return kShapeSphere;
    case ColliderShape::box: return kShapeBox;
    case ColliderShape::capsule: return kShapeCapsule;
    case ColliderShape::mesh: return kShapeMesh;
  }
  return -1.0;
}

// The two Vec3s of a shape's row (device_step.h: kColliderFirst, kColliderSecond); a mesh's
// arrays are its own (MeshArrays).
std::array<Vec3, 2> shape_vectors(const Collider& c) {
  switch (c.shape) {
    case ColliderShape::plane: return {c.point, c.normal};
    case ColliderShape::sphere: return {c.center, Vec3{}};
    case ColliderShape::box: return {c.center, c.half_extents};
    case ColliderShape::capsule: return {c.a, c.b};
    case ColliderShape::mesh: break;
  }
  return {Vec3{}, Vec3{}};
}

}  // namespace

MeshArrays mesh_arrays(const std::vector<Collider>& colliders) {
  MeshArrays arrays;
  arrays.uints.assign(std::max<std::size_t>(colliders.size(), 1) * kMeshHeaderUints, 0u);
  const auto append_vectors = [&](const std::vector<Vec3>& vectors) {
    for (const Vec3& v : vectors) arrays.reals.insert(arrays.reals.end(), {v.x, v.y, v.z});
  };
  for (std::size_t c = 0; c < colliders.size(); ++c) {
    if (colliders[c].shape != ColliderShape::mesh) continue;
    const TriangleMesh& mesh = *colliders[c].mesh;
    const auto header = static_cast<std::ptrdiff_t>(c * kMeshHeaderUints);
    const std::array<std::size_t, kMeshHeaderUints> counts = {
        arrays.reals.size(), arrays.uints.size(), mesh.vertex.size(), mesh.triangle.size(), mesh.node_low.size()};
    for (std::size_t k = 0; k < counts.size(); ++k) {
      arrays.uints[static_cast<std::size_t>(header) + k] = static_cast<std::uint32_t>(counts[k]);
    }
    append_vectors(mesh.vertex);
    append_vectors(mesh.vertex_pseudonormal);
    append_vectors(mesh.triangle_normal);
    append_vectors(mesh.edge_pseudonormal);
    append_vectors(mesh.node_low);
    append_vectors(mesh.node_high);
    for (const auto& corners : mesh.triangle) arrays.uints.insert(arrays.uints.end(), corners.begin(), corners.end());
    for (const auto* nodes : {&mesh.node_child, &mesh.node_first, &mesh.node_count, &mesh.node_triangle}) {
      arrays.uints.insert(arrays.uints.end(), nodes->begin(), nodes->end());
    }
  }
  if (arrays.reals.empty()) arrays.reals.push_back(0.0);  // a placeholder: every pass binds the array
  return arrays;
}

std::vector<double> collider_rows(const std::vector<Collider>& colliders, const CollisionSettings& collision,
                                  double t0) {
  std::vector<double> table;
  table.reserve(colliders.size() * kColliderReals);
  for (const Collider& collider : colliders) {
    const std::array<Vec3, 2> vectors = shape_vectors(collider);
    table.insert(table.end(), {shape_code(collider.shape), collider_friction(collider, collision), vectors[0].x,
                               vectors[0].y, vectors[0].z, vectors[1].x, vectors[1].y, vectors[1].z, collider.radius});
    // The path as the shape's offset from where it is given (collider_offset()).
    append_path_row(table, collider.path, t0, collider.path.position(0.0));
  }
  CLOTHSIM_ASSERT(table.size() == colliders.size() * kColliderReals, "a collider's row is device_step.h's");
  return table;
}

}  // namespace clothsim::gpu
