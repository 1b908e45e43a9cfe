// Implicit Euler's obstacle pass on the device (gpu/device_implicit_euler.h): the collision stage's
// obstacle pass after every step, with the CPU's contact law (shaders/obstacle_contacts.comp, the
// explicit methods' pass), its bookkeeping on DeviceForces' element arrays
// (shaders/obstacle_energy_elements.comp), and what the next step needs from it: the particles
// resting on a surface, which it holds, and the earliest impact ahead, which limits it. docs/gpu.md,
// "Implicit Euler on the device", says what differs from the CPU.
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "core/step_profile.h"
#include "gpu/device_colliders.h"
#include "gpu/device_implicit_euler.h"
#include "gpu/real_arrays.h"
#include "gpu/shaders/device_step.h"

namespace clothsim::gpu {
namespace {

std::uint32_t obstacle_workgroups(std::uint64_t items) { return workgroups_for(items, kReduceWorkgroup); }

}  // namespace

std::uint64_t DeviceImplicitEuler::obstacle_blocks(std::uint64_t particles, std::uint64_t connectors,
                                                   std::uint64_t radials) {
  return std::uint64_t{obstacle_workgroups(particles)} + obstacle_workgroups(connectors) + obstacle_workgroups(radials);
}

bool DeviceImplicitEuler::prepare_obstacles() {
  const std::size_t count = model_.colliders.size();
  const bool wanted = count > 0 || model_.collision.self;
  if (count == collider_count_ && wanted == obstacle_pass_) return false;
  // The colliders of a new model, or colliders added since the arrays were made (a live edit), or
  // self-collision switched on or off. Colliders are never removed, and a mesh never changes after
  // it is read.
  obstacle_pass_ = wanted;
  collider_count_ = count;
  if (!wanted) return true;
  constexpr std::array<Array, 9> kSized = {
      surface_contacts,      impulse,   start_position, contact_before, moved, colliders, obstacle_control_real,
      obstacle_control_uint, block_sums};
  const auto bytes = array_bytes(element_counts(model_), precision_, anchor_capacity_, count, true);
  const MeshArrays meshes = mesh_arrays(model_.colliders);
  const std::uint64_t real = real_size(precision_);
  std::uint64_t total = meshes.reals.size() * real + meshes.uints.size() * 4;
  for (Array a : kSized) total += bytes[a];
  device_.require_memory(total, "the obstacles");
  for (Array a : kSized) arrays_[a] = Buffer(device_, bytes[a], Memory::device_local);
  colliders_input_ = Buffer(device_, bytes[colliders], Memory::host_visible);
  arrays_[mesh_reals] = Buffer(device_, meshes.reals.size() * real, Memory::device_local);
  arrays_[mesh_uints] = Buffer(device_, meshes.uints.size() * 4, Memory::device_local);
  upload(device_, arrays_[mesh_reals], real_bytes(meshes.reals, precision_));
  upload(device_, arrays_[mesh_uints], std::as_bytes(std::span(meshes.uints)));
  // The pass runs on accepted steps only: the flag rk_control sets for the explicit methods is
  // always set here.
  std::vector<std::uint32_t> control(kControlUints, 0u);
  control[kAccepted] = 1u;
  upload(device_, arrays_[obstacle_control_uint], index_bytes<std::uint32_t>(control));
  return true;
}

void DeviceImplicitEuler::bind_obstacle_passes() {
  const auto own = [&](Array a) { return &arrays_[a]; };
  const auto shared = [&](DeviceForces::Array a) { return &forces_.buffer(a); };
  using F = DeviceForces;
  // The float32 state's low parts do not exist in implicit Euler (float64 only): the moved flags
  // stand in for them, never written (CLOTHSIM_STAGE_OFFSETS is float32's).
  obstacle_contacts_pass_.bind(
      std::vector<const Buffer*>{own(obstacle_control_real), own(obstacle_control_uint), own(start_position),
                                 shared(F::position), shared(F::velocity), own(particle_anchor), own(colliders),
                                 own(contact_before), own(moved), own(mesh_reals), own(mesh_uints), own(moved),
                                 own(moved), own(surface_contacts), own(impulse), own(hold), shared(F::particle_mass)});
  obstacle_elements_pass_.bind(std::vector<const Buffer*>{own(obstacle_control_real),
                                                          shared(F::position),
                                                          shared(F::velocity),
                                                          own(contact_before),
                                                          own(moved),
                                                          own(particle_anchor),
                                                          own(colliders),
                                                          shared(F::particle_mass),
                                                          shared(F::environment),
                                                          shared(F::connector_particles),
                                                          shared(F::connector_rest_length),
                                                          shared(F::connector_stiffness),
                                                          shared(F::connector_active),
                                                          shared(F::radial_particles),
                                                          shared(F::radial_rest_angle),
                                                          shared(F::radial_stiffness),
                                                          shared(F::radial_fade_length),
                                                          shared(F::radial_active),
                                                          own(block_sums),
                                                          own(mesh_reals),
                                                          own(mesh_uints),
                                                          own(surface_contacts),
                                                          own(impulse),
                                                          own(hold),
                                                          own(solve_uint)});
}

void DeviceImplicitEuler::record_obstacle_reduction(VkCommandBuffer commands, std::uint32_t blocks) const {
  ImplicitPassConstants reduce = constants(kReduceObstacles);
  reduce.blocks = blocks;
  reduce_pass_.dispatch(commands, &reduce, kImplicitReduceWorkgroup);
  record_solve_readback(commands);
}

// The surface contacts and the first limit at an advance's start: the particles' phase alone
// (nothing has moved). The pass after a step: the resolution; then, after the self pass where it
// runs, the booking: the three phases' blocks one after the other in block_sums, and their sums.
void DeviceImplicitEuler::record_obstacle_buffers() {
  const auto colliders_count = static_cast<std::uint32_t>(collider_count_);
  const std::uint32_t particle_blocks = obstacle_workgroups(particles_);
  contacts_commands_ = record_timed(2, [&](VkCommandBuffer commands, PassTimer& timer) {
    record_upload(commands, obstacle_input_, arrays_[obstacle_control_real], obstacle_input_.bytes());
    record_upload(commands, uint_input_, arrays_[solve_uint], uint_input_.bytes());
    record_upload(commands, colliders_input_, arrays_[colliders], colliders_input_.bytes());
    timer.mark(commands, StepStage::device_transfers);
    const ObstacleElementConstants start{particles_, kObstacleParticlesPhase, 0, colliders_count, 1};
    obstacle_elements_pass_.dispatch(commands, &start, particles_);
    record_obstacle_reduction(commands, particle_blocks);
    timer.mark(commands, StepStage::collisions);
  });
  obstacle_commands_ = record_timed(2, [&](VkCommandBuffer commands, PassTimer& timer) {
    record_upload(commands, obstacle_input_, arrays_[obstacle_control_real], obstacle_input_.bytes());
    timer.mark(commands, StepStage::device_transfers);
    const ObstaclePassConstants resolve{particles_, static_cast<std::uint32_t>(model_.rows),
                                        static_cast<std::uint32_t>(model_.cols), colliders_count, 1};
    obstacle_contacts_pass_.dispatch(commands, &resolve, particles_);
    timer.mark(commands, StepStage::collisions);
  });
  booking_commands_ = record_timed(1, [&](VkCommandBuffer commands, PassTimer& timer) {
    const std::array<std::uint32_t, 3> counts = {particles_, connectors_, radials_};
    std::uint32_t first_block = 0;
    for (std::uint32_t phase = kObstacleParticlesPhase; phase <= kObstacleRadialsPhase; ++phase) {
      const ObstacleElementConstants after{counts[phase], phase, first_block, colliders_count, 0};
      obstacle_elements_pass_.dispatch(commands, &after, counts[phase]);
      first_block += obstacle_workgroups(counts[phase]);
    }
    record_obstacle_reduction(commands, first_block);
    timer.mark(commands, StepStage::collisions);
  });
}

void DeviceImplicitEuler::write_obstacle_control(double tau0, double tau1) {
  std::byte* reals = obstacle_input_.mapped();
  for (std::uint32_t slot = 0; slot < kControlReals; ++slot) store_real(reals, slot, 0.0, precision_);
  store_real(reals, kStepStart, tau0, precision_);
  store_real(reals, kElapsed, tau1, precision_);
  store_real(reals, kThickness, model_.collision.thickness, precision_);
}

void DeviceImplicitEuler::read_obstacle_outputs(double time) {
  holding_ = output_uint(kResting) != 0;
  // A limit that rounds to the current time is no limit (ObstacleContacts::begin_step).
  const double arrival = output_real(kObstacleArrival);
  const double limit = time + arrival;
  step_limit_ = arrival < 0.5 * CLOTHSIM_NO_ARRIVAL && limit > time ? limit : std::numeric_limits<double>::infinity();
}

void DeviceImplicitEuler::begin_obstacles(double t0) {
  StageTimer timer(profile_, StepStage::collisions);
  // The colliders' paths over the advance from t0, into the staging the submission copies from.
  const std::vector<double> rows = collider_rows(model_.colliders, model_.collision, t0);
  std::byte* staging = colliders_input_.mapped();
  for (std::size_t k = 0; k < rows.size(); ++k) store_real(staging, k, rows[k], precision_);
  write_obstacle_control(0.0, 0.0);
  write_solve_counters();
  submit(contacts_commands_);
  read_obstacle_outputs(t0);
}

void DeviceImplicitEuler::resolve_obstacles(ClothState& state, double tau0, double tau1) {
  write_obstacle_control(tau0, tau1);
  submit(obstacle_commands_);
  const std::size_t unresolved = runs_self_contacts() ? resolve_self_contacts(tau1 - tau0) : 0;
  submit(booking_commands_);
  state.contact_work += output_real(kObstacleWork);
  const auto moved_particles = static_cast<std::size_t>(output_real(kObstacleMoved));
  contacts_.last = moved_particles;
  contacts_.steps += moved_particles;
  contacts_.most = std::max(contacts_.most, moved_particles);
  // The next step's forces are at the state the pass left, where it changed one.
  if (output_uint(kStateChanged) != 0) forces_current_ = false;
  read_obstacle_outputs(state.time);
  if (unresolved > 0) finish_self_contacts_on_host(state, tau1 - tau0);
}

IntegratorContacts DeviceImplicitEuler::take_obstacle_contacts() {
  return std::exchange(contacts_, IntegratorContacts{});
}

}  // namespace clothsim::gpu
