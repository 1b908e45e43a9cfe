// Implicit Euler on the device (gpu/device_implicit_euler.h): the state between the host and the
// device. What the host changed goes up before an advance (the model by its revision, with the
// laws' per-spring values; the state by its fingerprint), the state comes back after it, the
// frame's energies and checks are summed where the state is (gpu/state_checks.h), and a checkpoint
// takes the solve's warm start and the slipped flags.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/state_archive.h"
#include "gpu/device_implicit_euler.h"
#include "gpu/real_arrays.h"
#include "gpu/state_transfer.h"

namespace clothsim::gpu {

void DeviceImplicitEuler::upload_changes(const ClothState& state) {
  const bool model_changed = model_.revision != model_revision_ || !exchanged_;
  if (model_changed) {
    if (model_.revision != forces_.model_revision()) forces_.refresh(model_);
    upload(device_, arrays_[particle_anchor], index_bytes<std::int32_t>(model_.particle_anchor));
    upload_events();
    if (laws() != recorded_laws_) {
      // Limits edited between frames: the laws' passes recorded again for the laws that act now.
      release_buffers();
      record_buffers();
    }
    model_revision_ = model_.revision;
    forces_current_ = false;
  }
  const std::uint64_t fingerprint = state_fingerprint(state, options_.threads);
  if (model_changed || fingerprint != exchanged_fingerprint_) {
    gpu::write_state(device_, {&forces_.buffer(DeviceForces::position)}, {&forces_.buffer(DeviceForces::velocity)},
                     state_staging_, precision_, options_.threads, state);
    exchanged_fingerprint_ = fingerprint;
    exchanged_ = true;
    forces_current_ = false;
  }
}

void DeviceImplicitEuler::read_state(ClothState& state) {
  gpu::read_state(device_, {&forces_.buffer(DeviceForces::position)}, {&forces_.buffer(DeviceForces::velocity)},
                  state_staging_, precision_, options_.threads, state);
  exchanged_fingerprint_ = state_fingerprint(state, options_.threads);
}

std::optional<StateChecks> DeviceImplicitEuler::check_state(const ClothState& state, double explosion_stretch) {
  // The device's anchored particles are the host's: each step writes their paths' values.
  if (!state_checks_ || !StateChecksPass::runs_with(options_.terms)) return std::nullopt;
  upload_changes(state);
  return state_checks_->run(model_, options_.terms, explosion_stretch, [](VkCommandBuffer) {});
}

void DeviceImplicitEuler::transfer_state(StateArchive& archive) {
  Integrator::transfer_state(archive);
  std::vector<std::byte> bytes(std::uint64_t{particles_} * 3 * real_size(precision_));
  if (!archive.loading()) download(device_, arrays_[solution], bytes);
  std::vector<Vec3> dv = vectors_from_bytes(bytes, precision_);
  archive.array("implicit_euler.dv", dv);
  std::vector<std::uint32_t> slipped_words(particles_, 0u);
  if (!archive.loading()) download(device_, arrays_[slipped], std::as_writable_bytes(std::span(slipped_words)));
  std::vector<std::uint8_t> slipped_flags(slipped_words.begin(), slipped_words.end());
  archive.array("implicit_euler.slipped", slipped_flags);
  // Whether the next step reuses the forces of the last one's end: the restored run evaluates them
  // again (the same values), without counting them again.
  bool reused = forces_current_;
  archive.value("implicit_euler.evaluated_valid", reused);
  if (archive.loading()) {
    upload(device_, arrays_[solution], vector_bytes(dv, precision_));
    slipped_words.assign(slipped_flags.begin(), slipped_flags.end());
    upload(device_, arrays_[slipped], index_bytes<std::uint32_t>(slipped_words));
    uncounted_evaluation_ = reused;
    forces_current_ = false;
  }
}

}  // namespace clothsim::gpu
