// Implicit Euler's self-collision on the device (gpu/device_implicit_euler.h): the collision
// stage's self pass after each step's obstacle pass, on the state where it lives
// (gpu/device_self_contacts.h), the particles it moves entered in the obstacle pass's ledger so
// that one booking after both books both passes' work. Where the device's rounds leave pairs
// touching, the host's pass (collision/self_contacts.h) finishes the step on the state read back:
// its impact zones are the fail-safe, and it books its own work. docs/gpu.md, "Self-collision on
// the device".
#include <algorithm>
#include <utility>
#include <vector>

#include "core/step_profile.h"
#include "gpu/device_implicit_euler.h"
#include "gpu/real_arrays.h"
#include "gpu/state_transfer.h"

namespace clothsim::gpu {

void DeviceImplicitEuler::begin_self_contacts() {
  // A torn sheet has other triangles and edges; anchors set or let go and masses edited, other
  // inverse masses: the pass takes them in place where it can.
  if (!self_ || !self_->refresh(model_)) self_.emplace(device_, precision_, model_);
  // Found again at each advance's start, so that a run restored at a frame finds the same ones.
  self_->forget_candidates();
}

std::size_t DeviceImplicitEuler::resolve_self_contacts(double h) {
  StageTimer timer(profile_, StepStage::collisions);
  using F = DeviceForces;
  const SelfContactCounts counts =
      self_->apply(arrays_[start_position], forces_.buffer(F::position), forces_.buffer(F::velocity), h,
                   MovedLedger{&arrays_[contact_before], &arrays_[moved]});
  self_counts_.last = counts.contacts;
  self_counts_.steps += counts.contacts;
  self_counts_.most = std::max(self_counts_.most, counts.contacts);
  self_counts_.impacts += counts.impacts;
  return counts.unresolved;
}

void DeviceImplicitEuler::finish_self_contacts_on_host(ClothState& state, double h) {
  StageTimer timer(profile_, StepStage::collisions);
  using F = DeviceForces;
  // The state and the step's start from the device; the host's pass; the state back up.
  ClothState host = state;
  gpu::read_state(device_, {&forces_.buffer(F::position)}, {&forces_.buffer(F::velocity)}, state_staging_, precision_,
                  options_.threads, host);
  std::vector<std::byte> bytes(std::uint64_t{particles_} * 3 * real_size(precision_));
  download(device_, arrays_[start_position], bytes);
  const std::vector<Vec3> start = vectors_from_bytes(bytes, precision_);
  // A fresh pass each time: its candidates found now, whatever steps it finished before, so that a
  // restored run finishes the step as the saved one did.
  host_self_ = SelfContacts{};
  const SelfContactCounts counts = host_self_.apply(model_, host, start, h, options_.terms, options_.threads);
  gpu::write_state(device_, {&forces_.buffer(F::position)}, {&forces_.buffer(F::velocity)}, state_staging_, precision_,
                   options_.threads, host);
  state.contact_work = host.contact_work;
  self_counts_.impacts += counts.impacts;
  self_counts_.zones += counts.zones;
  self_counts_.unresolved += counts.unresolved;
  forces_current_ = false;
}

IntegratorSelfContacts DeviceImplicitEuler::take_self_contacts() { return std::exchange(self_counts_, {}); }

}  // namespace clothsim::gpu
