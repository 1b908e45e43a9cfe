// The colliders as both device integrators upload them (device_step.h: kColliderReals, the mesh
// arrays after kMeshHeaderUints): each collider's row with its path over an advance from t0, and
// the triangle meshes' arrays. The passes that read them (shaders/obstacle_surface.glsl) query
// the shapes with the CPU's text (model/collider_shapes.inc, model/mesh_distance.inc).
#pragma once

#include <cstdint>
#include <vector>

#include "model/collider.h"

namespace clothsim::gpu {

// The colliders' rows in collider order, kColliderReals each: the shape as given, its Coulomb
// coefficient against the sheet, and its path over the advance from t0 (gpu/device_paths.h).
std::vector<double> collider_rows(const std::vector<Collider>& colliders, const CollisionSettings& collision,
                                  double t0);

// The mesh colliders' arrays as the device reads them (device_step.h, kMeshHeaderUints), in
// collider order; a placeholder Real where there is no mesh (every pass binds the array).
struct MeshArrays {
  std::vector<double> reals;
  std::vector<std::uint32_t> uints;
};
MeshArrays mesh_arrays(const std::vector<Collider>& colliders);

}  // namespace clothsim::gpu
