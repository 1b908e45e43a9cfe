// Triangle meshes for tests of mesh colliders (model/collider.h): built in code, so the tests
// need no files.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "model/collider.h"

namespace clothsim {

// Each triangle wound counter-clockwise seen from outside: flipped when its
// normal points towards `inside_point`.
inline void add_triangle(TriangleMesh& mesh, std::array<std::uint32_t, 3> corner, const Vec3& inside_point) {
  const Vec3& a = mesh.vertex[corner[0]];
  const Vec3 normal = cross(mesh.vertex[corner[1]] - a, mesh.vertex[corner[2]] - a);
  if (dot(normal, a - inside_point) < 0.0) std::swap(corner[1], corner[2]);
  mesh.triangle.push_back(corner);
}

// A closed cube mesh: the box of centre `center` and half extents `half`, exactly.
inline std::shared_ptr<const TriangleMesh> cube_mesh(const Vec3& center, const Vec3& half) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) {  // corner i: bit 0 is +x, bit 1 +y, bit 2 +z
    mesh.vertex.push_back(center +
                          Vec3{(i & 1 ? 1 : -1) * half.x, (i & 2 ? 1 : -1) * half.y, (i & 4 ? 1 : -1) * half.z});
  }
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      std::vector<std::uint32_t> quad;  // corners around the face, in cyclic order
      const int u = (axis + 1) % 3;
      const int v = (axis + 2) % 3;
      for (const auto& [bu, bv] : std::array<std::array<int, 2>, 4>{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}}) {
        quad.push_back(static_cast<std::uint32_t>((side << axis) | (bu << u) | (bv << v)));
      }
      add_triangle(mesh, {quad[0], quad[1], quad[2]}, center);
      add_triangle(mesh, {quad[0], quad[2], quad[3]}, center);
    }
  }
  prepare_triangle_mesh(mesh);
  return std::make_shared<const TriangleMesh>(std::move(mesh));
}

}  // namespace clothsim
