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
#include "gpu/device_colliders.h"
#include "gpu/device_integrator.h"
#include "gpu/device_paths.h"
#include "gpu/real_arrays.h"
#include "gpu/shaders/device_step.h"

namespace clothsim::gpu {

void DeviceIntegrator::prepare_obstacles() {
  const std::size_t count = model_.colliders.size();
  if (count == collider_count_) return;
  // The colliders of a new model, or colliders added since the arrays were made (a live edit): the
  // arrays sized anew, the meshes uploaded, the passes bound to the arrays, and the attempts
  // recorded again with the obstacle passes. (Colliders are never removed, and a mesh never
  // changes after it is read.)
  CLOTHSIM_ASSERT(lattice_ || count == 0, "obstacles run on the device's lattice path only");
  const auto bytes =
      array_bytes(element_counts(model_), tableau_.stages, precision_, anchor_capacity_, count, chained_stages_);
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
  const std::vector<double> table = collider_rows(model_.colliders, model_.collision, t0);
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
                                        static_cast<std::uint32_t>(collider_count_), 0};
  obstacle_contacts_pass_.dispatch(commands, &constants, particles_);
  obstacle_energy_pass_.dispatch(commands, &constants, particles_);
  timer.mark(commands, StepStage::collisions);
}

IntegratorContacts DeviceIntegrator::take_obstacle_contacts() { return std::exchange(contacts_, IntegratorContacts{}); }

}  // namespace clothsim::gpu
