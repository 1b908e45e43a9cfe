// The Vulkan backend's integrator (gpu/device_integrator.h): the state between the host and the
// device. What the host changed goes up before an advance (the model by its revision, the state
// by its fingerprint), the state comes back after it, and the frame's energies and checks are
// summed where the state is (gpu/state_checks.h).
#include <optional>
#include <vector>

#include "gpu/device_integrator.h"
#include "gpu/real_arrays.h"
#include "gpu/state_transfer.h"

namespace clothsim::gpu {

void DeviceIntegrator::upload_changes(const ClothState& state) {
  // A changed model may have freed an anchored particle, whose state the device holds only as
  // its path left it: the state goes up with the model.
  const bool model_changed = model_.revision != model_revision_ || !exchanged_;
  if (model_changed) {
    if (model_.revision != forces_.model_revision()) forces_.refresh(model_);
    prepare_obstacles();
    upload(device_, arrays_[inverse_mass], real_bytes(model_.particle_inverse_mass, precision_));
    upload(device_, arrays_[particle_anchor], index_bytes<std::int32_t>(model_.particle_anchor));
    if (lattice_) upload_lattice_params();
    model_revision_ = model_.revision;
    set_laws();
  }
  const std::uint64_t fingerprint = state_fingerprint(state, options_.threads);
  if (model_changed || fingerprint != exchanged_fingerprint_) {
    // In float32 two floats a coordinate (shaders/split_state.glsl).
    const bool split = splits_state(precision_);
    gpu::write_state(device_, {&arrays_[state_position], split ? &arrays_[state_position_low] : nullptr},
                     {&arrays_[state_velocity], split ? &arrays_[state_velocity_low] : nullptr}, state_staging_,
                     precision_, options_.threads, state);
    exchanged_fingerprint_ = fingerprint;
    exchanged_ = true;
  }
}

void DeviceIntegrator::read_state(ClothState& state) {
  const bool split = splits_state(precision_);
  gpu::read_state(device_, {&arrays_[state_position], split ? &arrays_[state_position_low] : nullptr},
                  {&arrays_[state_velocity], split ? &arrays_[state_velocity_low] : nullptr}, state_staging_,
                  precision_, options_.threads, state);
}

std::optional<StateChecks> DeviceIntegrator::check_state(const ClothState& state, double explosion_stretch) {
  if (!state_checks_ || !StateChecksPass::runs_with(options_.terms)) return std::nullopt;
  upload_changes(state);
  // The anchored particles as the host put them on their paths at the advance's end
  // (take_results): the device's own copy, which its steps never read, is its paths' in its
  // precision, and its velocity the last segment's at a key.
  std::vector<std::uint32_t> anchored;
  anchored.reserve(model_.anchors.size());
  for (const Anchor& anchor : model_.anchors) anchored.push_back(anchor.particle);
  const std::uint64_t bytes = particle_write_bytes(anchored.size(), precision_);
  if (input_staging_.bytes() < bytes) input_staging_ = Buffer(device_, bytes, Memory::host_visible);
  const bool split = splits_state(precision_);
  const StateArray position{&arrays_[state_position], split ? &arrays_[state_position_low] : nullptr};
  const StateArray velocity{&arrays_[state_velocity], split ? &arrays_[state_velocity_low] : nullptr};
  return state_checks_->run(model_, options_.terms, explosion_stretch, [&](VkCommandBuffer commands) {
    record_particle_writes(commands, position, velocity, input_staging_, precision_, anchored, state);
  });
}

}  // namespace clothsim::gpu
