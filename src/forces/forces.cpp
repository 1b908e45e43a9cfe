#include "forces/forces.h"

#include <algorithm>

#include "core/assert.h"
#include "core/parallel.h"

namespace clothsim {
namespace {

// Block size of deterministic reductions. It is fixed, not derived from the thread count, so the
// grouping of the sum (and hence its rounding) never changes.
constexpr std::size_t kReductionBlock = 1024;

}  // namespace

void ForceBuffers::resize(const ClothModel& model) {
  const bool lattice_ready = kernel != ForceKernel::general && lattice.prepare(model, precision, both_precisions);
  if (kernel == ForceKernel::general) lattice = LatticeKernel{};
  CLOTHSIM_ASSERT(kernel != ForceKernel::lattice || lattice_ready,
                  "ForceKernel::lattice needs a model with the lattice layout");
  CLOTHSIM_ASSERT(precision == Precision::float64 || lattice_ready,
                  "float32 forces are the lattice kernel's: a model with the lattice layout, kernel not general");
  if (lattice_ready) {
    // Released, not just cleared: a ForceBuffers resized for another model may hold them.
    std::vector<Vec3>().swap(slot_force);
    std::vector<double>().swap(element_power);
    std::vector<double>().swap(block_power);
    gather = GatherTable{};
    return;
  }
  gather.build(model);
  slot_force.assign(model.force_slot_count(), Vec3{});
  element_power.assign(model.connector_count() + model.radial_count(), 0.0);
  block_power.assign((element_power.size() + kReductionBlock - 1) / kReductionBlock, 0.0);
}

void ForceBuffers::set_precision(const ClothModel& model, Precision next) {
  CLOTHSIM_ASSERT(uses_lattice_kernel(), "float32 forces are the lattice kernel's");
  precision = next;
  lattice.set_precision(model, next);
}

std::size_t ForceBuffers::bytes() const {
  return slot_force.capacity() * sizeof(Vec3) + (element_power.capacity() + block_power.capacity()) * sizeof(double) +
         gather.bytes() + lattice.bytes();
}

std::size_t ForceBuffers::bytes_for(const LatticeCounts& counts, ForceKernel kernel, bool parameter_arrays,
                                    Precision precision) {
  if (kernel != ForceKernel::general) return LatticeKernel::bytes_for(counts, parameter_arrays, precision);
  const std::size_t elements = counts.connectors + counts.radials;
  const std::size_t slots = 2 * counts.connectors + 3 * counts.radials;
  return slots * sizeof(decltype(slot_force)::value_type) +
         (elements + (elements + kReductionBlock - 1) / kReductionBlock) * sizeof(decltype(element_power)::value_type) +
         GatherTable::bytes_for(counts);
}

std::size_t deterministic_sum_blocks(std::size_t count) { return (count + kReductionBlock - 1) / kReductionBlock; }

namespace {

template <typename Real>
double deterministic_sum_of(std::span<const Real> values, int threads, std::vector<double>& block_sums) {
  const std::size_t blocks = (values.size() + kReductionBlock - 1) / kReductionBlock;
  CLOTHSIM_ASSERT(block_sums.size() >= blocks, "block buffer sized by ForceBuffers::resize");
  parallel_for(blocks, threads, [&](std::size_t block) {
    const std::size_t begin = block * kReductionBlock;
    const std::size_t end = std::min(values.size(), begin + kReductionBlock);
    double sum = 0.0;
    for (std::size_t i = begin; i < end; ++i) sum += values[i];
    block_sums[block] = sum;
  });
  double total = 0.0;
  for (std::size_t block = 0; block < blocks; ++block) total += block_sums[block];
  return total;
}

}  // namespace

double deterministic_sum(std::span<const double> values, int threads, std::vector<double>& block_sums) {
  return deterministic_sum_of(values, threads, block_sums);
}

double deterministic_sum(std::span<const float> values, int threads, std::vector<double>& block_sums) {
  return deterministic_sum_of(values, threads, block_sums);
}

void gather_forces(const ClothModel& model, std::span<const Vec3> velocity, ForceTerms terms, int threads,
                   const ForceBuffers& buffers, std::span<Vec3> force) {
  const Vec3 gravity = (terms & kGravity) != 0 ? model.environment.gravity : Vec3{};
  const double drag = (terms & kAirDrag) != 0 ? model.environment.air_drag : 0.0;
  parallel_for(model.particle_count(), threads, [&](std::size_t p) {
    Vec3 sum = model.particle_mass[p] * gravity - drag * velocity[p];
    for (std::uint32_t k = buffers.gather.offset[p]; k < buffers.gather.offset[p + 1]; ++k) {
      sum += buffers.slot_force[buffers.gather.slot[k]];
    }
    force[p] = sum;
  });
}

ForcePowers evaluate_forces(const ClothModel& model, std::span<const Vec3> position, std::span<const Vec3> velocity,
                            ForceTerms terms, int threads, ForceBuffers& buffers, std::span<Vec3> force) {
  ForcePowers powers;
  if (buffers.lattice.active()) {
    powers.damping = buffers.lattice.evaluate(model, position, velocity, terms, threads, force);
  } else {
    CLOTHSIM_ASSERT(buffers.slot_force.size() == model.force_slot_count(), "ForceBuffers::resize(model) was called");
    accumulate_connector_springs(model, position, velocity, terms, threads, buffers);
    accumulate_radial_springs(model, position, velocity, terms, threads, buffers);
    gather_forces(model, velocity, terms, threads, buffers, force);
    powers.damping = deterministic_sum(buffers.element_power, threads, buffers.block_power);
  }
  if ((terms & kAirDrag) != 0 && model.environment.air_drag != 0.0) {
    // -drag |v|^2 summed in particle order. Serial: it is one multiply-add per particle.
    double speed_squared = 0.0;
    for (std::size_t p = 0; p < model.particle_count(); ++p) speed_squared += squared_norm(velocity[p]);
    powers.drag = -model.environment.air_drag * speed_squared;
  }
  return powers;
}

EnergyReport compute_energy(const ClothModel& model, const ClothState& state, ForceTerms terms, int threads) {
  EnergyReport report;
  report.kinetic = kinetic_energy(model, state.velocity, threads);
  if ((terms & kGravity) != 0) report.gravitational = gravitational_energy(model, state.position, threads);
  if ((terms & kConnectorSprings) != 0) report.connector = connector_energy(model, state.position, threads);
  EnergyReport radial;
  add_radial_energy(model, state.position, radial, threads);
  if ((terms & kAdjacentRadialSprings) != 0) report.radial_adjacent = radial.radial_adjacent;
  if ((terms & kOppositeRadialSprings) != 0) report.radial_opposite = radial.radial_opposite;
  return report;
}

}  // namespace clothsim
