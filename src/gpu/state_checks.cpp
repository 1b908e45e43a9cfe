#include "gpu/state_checks.h"

#include <cstring>
#include <vector>

#include "core/assert.h"
#include "gpu/shaders/state_checks.h"

namespace clothsim::gpu {
namespace {

constexpr std::uint32_t kBindings = 8;

std::uint64_t block_bytes(std::uint64_t particles) {
  return std::uint64_t{workgroups_for(particles, kStateChecksWorkgroup)} * kStateCheckReals * sizeof(double);
}

}  // namespace

std::uint64_t StateChecksPass::bytes_for(std::uint64_t particles) { return block_bytes(particles); }

StateChecksPass::StateChecksPass(Device& device, Precision precision, std::uint32_t particles)
    : device_(device),
      particles_(particles),
      blocks_(workgroups_for(particles, kStateChecksWorkgroup)),
      pass_(shader_pipeline(device, "state_checks", precision, kBindings, sizeof(StateCheckConstants),
                            kStateChecksWorkgroup)),
      block_checks_(device, block_bytes(particles), Memory::device_local),
      readback_(device, block_bytes(particles), Memory::host_visible) {
  CLOTHSIM_ASSERT(runs_on(device), "the state checks need shaderFloat64");
}

void StateChecksPass::bind(StateArray position, StateArray velocity, const Buffer& mass, const Buffer& lattice_params,
                           const Buffer& event_params) {
  // float64 has no low parts: the high arrays stand in for them, unread.
  const Buffer* position_low = position.low != nullptr ? position.low : position.high;
  const Buffer* velocity_low = velocity.low != nullptr ? velocity.low : velocity.high;
  const std::vector<const Buffer*> buffers{position.high, velocity.high, position_low, velocity_low,
                                           &mass,         &lattice_params, &event_params, &block_checks_};
  pass_.bind(buffers);
}

StateCheckSums StateChecksPass::run(const ClothModel& model, double explosion_stretch,
                                    const std::function<void(VkCommandBuffer)>& before) {
  const Vec3& gravity = model.environment.gravity;
  const StateCheckConstants constants{particles_,
                                      static_cast<std::uint32_t>(model.rows),
                                      static_cast<std::uint32_t>(model.cols),
                                      0u,
                                      gravity.x,
                                      gravity.y,
                                      gravity.z,
                                      explosion_stretch};
  device_.submit([&](VkCommandBuffer commands) {
    before(commands);
    pass_.dispatch(commands, &constants, particles_);
    record_readback(commands, block_checks_, readback_, readback_.bytes());
  });
  // The workgroups' sums in order: the same result on every run.
  std::vector<double> blocks(std::size_t{blocks_} * kStateCheckReals);
  std::memcpy(blocks.data(), readback_.mapped(), blocks.size() * sizeof(double));
  double sums[kStateCheckReals] = {};
  for (std::size_t block = 0; block < blocks_; ++block) {
    for (std::size_t k = 0; k < kStateCheckReals; ++k) sums[k] += blocks[block * kStateCheckReals + k];
  }
  StateCheckSums result;
  result.energy.kinetic = sums[kCheckKinetic];
  result.energy.gravitational = sums[kCheckGravitational];
  result.energy.connector = sums[kCheckConnector];
  result.energy.radial_adjacent = sums[kCheckRadialAdjacent];
  result.energy.radial_opposite = sums[kCheckRadialOpposite];
  result.failures = static_cast<std::uint64_t>(sums[kCheckFailures]);
  return result;
}

}  // namespace clothsim::gpu
