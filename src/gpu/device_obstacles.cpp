// The Vulkan backend's obstacle pass on the host side (gpu/device_integrator.h): the colliders'
// rows, the arrays the two obstacle passes use, the first step's limit, and the passes recorded
// into an attempt. The passes themselves (shaders/obstacle_contacts.comp, obstacle_energy.comp)
// run the CPU's contact law (collision/obstacle_contact.inc) on the analytic shapes
// (model/collider_shapes.inc); docs/gpu.md, "Obstacles on the device", says what differs.
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "core/assert.h"
#include "core/step_profile.h"
#include "gpu/device_integrator.h"
#include "gpu/device_paths.h"
#include "gpu/real_arrays.h"
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

// The mesh colliders' arrays as the device reads them (device_step.h, kMeshHeaderUints), in
// collider order.
struct MeshArrays {
  std::vector<double> reals;
  std::vector<std::uint32_t> uints;
};

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
    const std::array<std::size_t, kMeshHeaderUints> counts = {arrays.reals.size(), arrays.uints.size(),
                                                              mesh.vertex.size(), mesh.triangle.size(),
                                                              mesh.node_low.size()};
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

}  // namespace

void DeviceIntegrator::prepare_obstacles() {
  const std::size_t count = model_.colliders.size();
  if (count == collider_count_) return;
  // The colliders of a new model, or colliders added since the arrays were made (a live edit): the
  // arrays sized anew, the meshes uploaded, the passes bound to the arrays, and the attempts
  // recorded again with the obstacle passes. (Colliders are never removed, and a mesh never
  // changes after it is read.)
  CLOTHSIM_ASSERT(lattice_ || count == 0, "obstacles run on the device's lattice path only");
  const auto bytes = array_bytes(element_counts(model_), tableau_.stages, precision_, anchor_capacity_, count);
  constexpr std::array<Array, 4> kSized = {colliders, contact_before, moved, block_obstacles};
  const MeshArrays meshes = mesh_arrays(model_.colliders);
  const std::uint64_t real = real_size(precision_);
  std::uint64_t total = meshes.reals.size() * real + meshes.uints.size() * 4;
  for (Array a : kSized) total += bytes[a];
  if (count > 0) device_.require_memory(total, "the obstacles");
  for (Array a : kSized) arrays_[a] = Buffer(device_, bytes[a], Memory::device_local);
  arrays_[mesh_reals] = Buffer(device_, meshes.reals.size() * real, Memory::device_local);
  arrays_[mesh_uints] = Buffer(device_, meshes.uints.size() * 4, Memory::device_local);
  upload(device_, arrays_[mesh_reals], real_bytes(meshes.reals, precision_));
  upload(device_, arrays_[mesh_uints], std::as_bytes(std::span(meshes.uints)));
  collider_count_ = count;
  bind_passes();
  release_recorded();
}

void DeviceIntegrator::upload_colliders(double t0) {
  if (!runs_obstacle_contacts()) return;
  std::vector<double> table;
  table.reserve(model_.colliders.size() * kColliderReals);
  for (const Collider& collider : model_.colliders) {
    const std::array<Vec3, 2> vectors = shape_vectors(collider);
    table.insert(table.end(), {shape_code(collider.shape), collider_friction(collider, model_.collision), vectors[0].x,
                             vectors[0].y, vectors[0].z, vectors[1].x, vectors[1].y, vectors[1].z, collider.radius});
    // The path as the shape's offset from where it is given (collider_offset()).
    append_path_row(table, collider.path, t0, collider.path.position(0.0));
  }
  CLOTHSIM_ASSERT(table.size() == model_.colliders.size() * kColliderReals, "a collider's row is device_step.h's");
  upload_input(arrays_[colliders], real_bytes(table, precision_));
}

double DeviceIntegrator::first_arrival(const ClothState& state) {
  if (!runs_obstacle_contacts()) return std::numeric_limits<double>::infinity();
  StageTimer timer(profile_, StepStage::collisions);
  return first_arrival_.begin_step(model_, state, options_.threads);
}

void DeviceIntegrator::record_obstacle_passes(VkCommandBuffer commands, PassTimer& timer) const {
  const ObstaclePassConstants constants{particles_, static_cast<std::uint32_t>(model_.rows),
                                        static_cast<std::uint32_t>(model_.cols),
                                        static_cast<std::uint32_t>(collider_count_)};
  obstacle_contacts_pass_.dispatch(commands, &constants, particles_);
  obstacle_energy_pass_.dispatch(commands, &constants, particles_);
  timer.mark(commands, StepStage::collisions);
}

IntegratorContacts DeviceIntegrator::take_obstacle_contacts() { return std::exchange(contacts_, IntegratorContacts{}); }

}  // namespace clothsim::gpu
