#include "gpu/state_checks.h"

#include <array>
#include <cstring>
#include <vector>

#include "core/assert.h"
#include "gpu/shaders/state_checks.h"

namespace clothsim::gpu {
namespace {

// The bindings: the state's four arrays, the masses and the sums (shaders/state_checks.glsl),
// then the lattice path's two parameter arrays, or the general path's nine element arrays.
constexpr std::uint32_t kLatticeBindings = 8;
constexpr std::uint32_t kElementBindings = 15;

std::uint32_t blocks_of(std::uint64_t items) { return workgroups_for(items, kStateChecksWorkgroup); }

// The workgroups of each dispatch: the lattice path's one over the particles, or the general
// path's three over the particles, the connectors and the radial springs, in that order.
std::array<std::uint32_t, 3> dispatch_blocks(const LatticeCounts& counts, DeviceForcePath path) {
  if (path == DeviceForcePath::lattice) return {blocks_of(counts.particles), 0, 0};
  return {blocks_of(counts.particles), blocks_of(counts.connectors), blocks_of(counts.radials)};
}

std::uint64_t block_bytes(const LatticeCounts& counts, DeviceForcePath path) {
  std::uint64_t blocks = 0;
  for (std::uint32_t b : dispatch_blocks(counts, path)) blocks += b;
  return std::max<std::uint64_t>(blocks, 1) * kStateCheckReals * sizeof(double);
}

}  // namespace

std::uint64_t StateChecksPass::bytes_for(const LatticeCounts& counts, DeviceForcePath path) {
  return block_bytes(counts, path);
}

StateChecksPass::StateChecksPass(Device& device, Precision precision, const LatticeCounts& counts,
                                 DeviceForcePath path)
    : device_(device),
      path_(path),
      counts_(counts),
      pass_(path == DeviceForcePath::lattice
                ? shader_pipeline(device, "state_checks", precision, kLatticeBindings, sizeof(StateCheckConstants),
                                  kStateChecksWorkgroup)
                : shader_pipeline(device, "state_checks_elements", precision, kElementBindings,
                                  sizeof(ElementCheckConstants), kStateChecksWorkgroup)),
      block_checks_(device, block_bytes(counts, path), Memory::device_local),
      readback_(device, block_bytes(counts, path), Memory::host_visible) {
  CLOTHSIM_ASSERT(runs_on(device), "the state checks need shaderFloat64");
}

namespace {

// The state's arrays, the masses and the sums, as shaders/state_checks.glsl binds them. float64
// has no low parts: the high arrays stand in for them, unread.
std::vector<const Buffer*> state_bindings(StateArray position, StateArray velocity, const Buffer& mass,
                                          const Buffer& block_checks) {
  return {position.high,
          velocity.high,
          position.low != nullptr ? position.low : position.high,
          velocity.low != nullptr ? velocity.low : velocity.high,
          &mass,
          &block_checks};
}

}  // namespace

void StateChecksPass::bind_lattice(StateArray position, StateArray velocity, const Buffer& mass,
                                   const Buffer& lattice_params, const Buffer& event_params) {
  CLOTHSIM_ASSERT(path_ == DeviceForcePath::lattice, "bind_lattice: a lattice path's pass");
  std::vector<const Buffer*> buffers = state_bindings(position, velocity, mass, block_checks_);
  buffers.push_back(&lattice_params);
  buffers.push_back(&event_params);
  pass_.bind(buffers);
}

void StateChecksPass::bind_elements(StateArray position, StateArray velocity, DeviceForces& forces) {
  CLOTHSIM_ASSERT(path_ == DeviceForcePath::general, "bind_elements: a general path's pass");
  using F = DeviceForces;
  std::vector<const Buffer*> buffers = state_bindings(position, velocity, forces.buffer(F::particle_mass),
                                                      block_checks_);
  for (F::Array a : {F::connector_particles, F::connector_rest_length, F::connector_stiffness, F::connector_active,
                     F::radial_particles, F::radial_rest_angle, F::radial_stiffness, F::radial_fade_length,
                     F::radial_active}) {
    buffers.push_back(&forces.buffer(a));
  }
  pass_.bind(buffers);
}

StateChecks StateChecksPass::run(const ClothModel& model, ForceTerms terms, double explosion_stretch,
                                 const std::function<void(VkCommandBuffer)>& before) {
  const Vec3& gravity = model.environment.gravity;
  const std::array<std::uint32_t, 3> blocks = dispatch_blocks(counts_, path_);
  device_.submit([&](VkCommandBuffer commands) {
    before(commands);
    if (path_ == DeviceForcePath::lattice) {
      const auto particles = static_cast<std::uint32_t>(counts_.particles);
      const StateCheckConstants constants{particles, static_cast<std::uint32_t>(model.rows),
                                          static_cast<std::uint32_t>(model.cols), 0u, gravity.x, gravity.y,
                                          gravity.z, explosion_stretch};
      pass_.dispatch(commands, &constants, particles);
    } else {
      const std::array<std::size_t, 3> items{counts_.particles, counts_.connectors, counts_.radials};
      std::uint32_t first_block = 0;
      for (std::uint32_t phase : {kCheckParticlesPhase, kCheckConnectorsPhase, kCheckRadialsPhase}) {
        const auto count = static_cast<std::uint32_t>(items[phase]);
        const ElementCheckConstants constants{count,     phase,     first_block, 0u, gravity.x,
                                              gravity.y, gravity.z, explosion_stretch};
        if (count > 0) pass_.dispatch(commands, &constants, count);
        first_block += blocks[phase];
      }
    }
    record_readback(commands, block_checks_, readback_, readback_.bytes());
  });
  // The workgroups' sums in order: the same result on every run.
  std::vector<double> sums_of_blocks(readback_.bytes() / sizeof(double));
  std::memcpy(sums_of_blocks.data(), readback_.mapped(), readback_.bytes());
  const std::size_t rows = std::size_t{blocks[0]} + blocks[1] + blocks[2];
  std::array<double, kStateCheckReals> sums{};
  for (std::size_t row = 0; row < rows; ++row) {
    for (std::size_t k = 0; k < kStateCheckReals; ++k) sums[k] += sums_of_blocks[row * kStateCheckReals + k];
  }
  StateChecks result;
  result.energy.kinetic = sums[kCheckKinetic];
  result.energy.gravitational = (terms & kGravity) != 0 ? sums[kCheckGravitational] : 0.0;
  result.energy.connector = sums[kCheckConnector];
  result.energy.radial_adjacent = sums[kCheckRadialAdjacent];
  result.energy.radial_opposite = sums[kCheckRadialOpposite];
  result.failed = sums[kCheckFailures] > 0.0;
  return result;
}

}  // namespace clothsim::gpu
