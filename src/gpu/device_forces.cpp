#include "gpu/device_forces.h"

#include <array>
#include <string>

#include "core/assert.h"
#include "forces/forces.h"
#include "gpu/gpu_error.h"
#include "gpu/real_arrays.h"
#include "gpu/shaders/element_pass.h"
#include "model/gather_table.h"

namespace clothsim::gpu {
namespace {

// The blocks of the damping power's sum: forces.cpp's kReductionBlock, so that the device adds
// the same numbers in the same order.
constexpr std::uint32_t kReductionBlock = 1024;

// Not 0 where the element acts: live and its force term on (the CPU's condition in
// connector_springs.cpp and radial_springs.cpp). A radial spring's flag is its kind besides,
// kRadialActiveAdjacent or kRadialActiveOpposite, which the state checks sum the energies by
// (shaders/state_checks_elements.comp).
std::vector<std::uint32_t> connector_active_flags(const ClothModel& model, ForceTerms terms) {
  std::vector<std::uint32_t> active(model.connector_count(), 0u);
  if ((terms & kConnectorSprings) == 0) return active;
  for (std::size_t e = 0; e < active.size(); ++e) active[e] = model.connector_live[e] != 0 ? 1u : 0u;
  return active;
}

std::vector<std::uint32_t> radial_active_flags(const ClothModel& model, ForceTerms terms) {
  std::vector<std::uint32_t> active(model.radial_count(), 0u);
  for (std::size_t r = 0; r < active.size(); ++r) {
    const ForceTerms term =
        model.radial_kind[r] == RadialKind::adjacent ? kAdjacentRadialSprings : kOppositeRadialSprings;
    const std::uint32_t kind =
        model.radial_kind[r] == RadialKind::adjacent ? kRadialActiveAdjacent : kRadialActiveOpposite;
    active[r] = (terms & term) != 0 && model.radial_live[r] != 0 ? kind : 0u;
  }
  return active;
}

std::uint32_t count32(std::size_t count, const char* what) {
  if (count > UINT32_MAX / 9) throw GpuError(std::string("too many ") + what + " for 32-bit indices on the device");
  return static_cast<std::uint32_t>(count);
}

// The checks before anything is made on the device.
Device& checked(Device& device, const ClothModel& model, Precision precision, std::uint32_t power_slots,
                DeviceForcePath path) {
  device.require_precision(precision);
  device.require_memory(DeviceForces::bytes_for(element_counts(model), precision, power_slots, path), "the scene");
  return device;
}

// The arrays the lattice path reads (the rest serve the element passes alone).
bool lattice_reads(DeviceForces::Array array) {
  using A = DeviceForces;
  return array == A::position || array == A::velocity || array == A::particle_mass || array == A::environment;
}

// The size of an array that no pass reads: a storage buffer may not be empty, and the passes
// that declare it (stage_acceleration, rk_accept) skip it on the lattice path.
constexpr std::uint64_t kPlaceholderBytes = 16;

// The model's arrays as the device holds them (the other arrays are state and scratch: empty).
std::array<std::vector<std::byte>, DeviceForces::array_count> model_contents(const ClothModel& model,
                                                                             Precision precision, ForceTerms terms,
                                                                             DeviceForcePath path) {
  using A = DeviceForces;
  const Vec3 gravity = (terms & kGravity) != 0 ? model.environment.gravity : Vec3{};
  const double drag = (terms & kAirDrag) != 0 ? model.environment.air_drag : 0.0;
  const std::array<double, 4> environment_values = {gravity.x, gravity.y, gravity.z, drag};
  std::array<std::vector<std::byte>, A::array_count> contents;
  contents[A::particle_mass] = real_bytes(model.particle_mass, precision);
  contents[A::environment] = real_bytes(environment_values, precision);
  if (path == DeviceForcePath::lattice) return contents;
  if (splits_state(precision)) {
    contents[A::origin_position] = contents[A::origin_velocity] =
        std::vector<std::byte>(std::size_t{3} * model.particle_count() * real_size(precision));
  }
  GatherTable gather;
  gather.build(model);
  contents[A::gather_offset] = index_bytes(std::span<const std::uint32_t>(gather.offset));
  contents[A::gather_slot] = index_bytes(std::span<const std::uint32_t>(gather.slot));
  contents[A::connector_particles] = index_bytes(std::span(model.connector_particles));
  contents[A::connector_rest_length] = real_bytes(model.connector_rest_length, precision);
  contents[A::connector_stiffness] = real_bytes(model.connector_stiffness, precision);
  contents[A::connector_damping] = real_bytes(model.connector_damping, precision);
  contents[A::connector_active] = index_bytes(std::span<const std::uint32_t>(connector_active_flags(model, terms)));
  contents[A::radial_particles] = index_bytes(std::span(model.radial_particles));
  contents[A::radial_rest_angle] = real_bytes(model.radial_rest_angle, precision);
  contents[A::radial_stiffness] = real_bytes(model.radial_stiffness, precision);
  contents[A::radial_damping] = real_bytes(model.radial_damping, precision);
  std::vector<double> fade_lengths(2 * model.radial_count());
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    const std::array<double, 2> fade = radial_fade_lengths(model, r);
    fade_lengths[2 * r] = fade[0];
    fade_lengths[2 * r + 1] = fade[1];
  }
  contents[A::radial_fade_length] = real_bytes(fade_lengths, precision);
  contents[A::radial_active] = index_bytes(std::span<const std::uint32_t>(radial_active_flags(model, terms)));
  return contents;
}

// The size of every array, bytes.
std::array<std::uint64_t, DeviceForces::array_count> array_bytes(const LatticeCounts& counts, Precision precision,
                                                                 std::uint32_t power_slots, DeviceForcePath path) {
  using A = DeviceForces;
  const std::uint64_t real = real_size(precision);
  const std::uint64_t particles = counts.particles;
  const std::uint64_t connectors = counts.connectors;
  const std::uint64_t radials = counts.radials;
  const std::uint64_t slots = 2 * connectors + 3 * radials;  // ClothModel::force_slot_count()
  std::array<std::uint64_t, A::array_count> bytes{};
  bytes[A::particle_mass] = particles * real;
  bytes[A::environment] = 4 * real;
  bytes[A::gather_offset] = (particles + 1) * 4;
  bytes[A::gather_slot] = slots * 4;
  bytes[A::connector_particles] = connectors * 2 * 4;
  bytes[A::connector_rest_length] = bytes[A::connector_stiffness] = bytes[A::connector_damping] = connectors * real;
  bytes[A::connector_active] = connectors * 4;
  bytes[A::radial_particles] = radials * 3 * 4;
  bytes[A::radial_rest_angle] = bytes[A::radial_stiffness] = bytes[A::radial_damping] = radials * real;
  bytes[A::radial_fade_length] = 2 * radials * real;
  bytes[A::radial_active] = radials * 4;
  bytes[A::position] = bytes[A::velocity] = bytes[A::force] = particles * 3 * real;
  // Read in float32 only (gpu/shaders/stage_offsets.glsl).
  bytes[A::origin_position] = bytes[A::origin_velocity] =
      splits_state(precision) ? particles * 3 * real : kPlaceholderBytes;
  bytes[A::slot_force] = slots * 3 * real;
  bytes[A::element_power] = (connectors + radials) * power_slots * real;
  bytes[A::block_power] = (connectors + radials + kReductionBlock - 1) / kReductionBlock * real;
  bytes[A::damping_power] = real;
  if (path == DeviceForcePath::lattice) {
    for (std::uint32_t a = 0; a < A::array_count; ++a) {
      if (!lattice_reads(static_cast<A::Array>(a))) bytes[a] = kPlaceholderBytes;
    }
  }
  return bytes;
}

}  // namespace

LatticeCounts element_counts(const ClothModel& model) {
  LatticeCounts counts;
  counts.particles = model.particle_count();
  counts.connectors = model.connector_count();
  counts.radials = model.radial_count();
  if (model.rows > 0 && model.cols > 0 &&
      static_cast<std::size_t>(model.rows) * static_cast<std::size_t>(model.cols) == counts.particles) {
    counts.rows = static_cast<std::size_t>(model.rows);
    counts.cols = static_cast<std::size_t>(model.cols);
  }
  CLOTHSIM_ASSERT(model.force_slot_count() == 2 * counts.connectors + 3 * counts.radials,
                  "two force slots per connector, three per radial spring");
  return counts;
}

std::uint64_t DeviceForces::bytes_for(const LatticeCounts& counts, Precision precision, std::uint32_t power_slots,
                                      DeviceForcePath path) {
  std::uint64_t total = 0;
  for (std::uint64_t bytes : array_bytes(counts, precision, power_slots, path)) total += bytes;
  return total;
}

DeviceForces::DeviceForces(Device& device, const ClothModel& model, Precision precision, ForceTerms terms,
                           std::uint32_t power_slots, DeviceForcePath path)
    : device_(checked(device, model, precision, power_slots, path)),
      precision_(precision),
      terms_(terms),
      power_slots_(power_slots),
      path_(path),
      model_revision_(model.revision),
      particles_(count32(model.particle_count(), "particles")),
      connectors_(count32(model.connector_count(), "connectors")),
      radials_(count32(model.radial_count(), "radial springs")),
      connector_pass_(
          shader_pipeline(device, "accumulate_connector_springs", precision, 11, sizeof(ElementPassConstants))),
      radial_pass_(shader_pipeline(device, "accumulate_radial_springs", precision, 12, sizeof(ElementPassConstants))),
      gather_pass_(shader_pipeline(device, "gather_forces", precision, 7, sizeof(GatherConstants))),
      sum_pass_(shader_pipeline(device, "deterministic_sum", precision, 3, sizeof(SumConstants))) {
  const std::array<std::uint64_t, array_count> bytes = array_bytes(element_counts(model), precision, power_slots, path);
  arrays_.reserve(array_count);
  for (std::uint32_t a = 0; a < array_count; ++a) arrays_.emplace_back(device_, bytes[a], Memory::device_local);
  upload_model(model);
  const auto bind = [&](ComputePipeline& pipeline, std::initializer_list<Array> list) {
    std::vector<const Buffer*> buffers;
    for (Array a : list) buffers.push_back(&arrays_[a]);
    pipeline.bind(buffers);
  };
  read_origin_from(arrays_[origin_position], arrays_[origin_velocity]);
  bind(gather_pass_, {velocity, particle_mass, environment, gather_offset, gather_slot, slot_force, force});
  bind(sum_pass_, {element_power, block_power, damping_power});
}

void DeviceForces::read_origin_from(const Buffer& origin_position_array, const Buffer& origin_velocity_array) {
  const auto own = [&](Array a) { return &arrays_[a]; };
  connector_pass_.bind(std::vector<const Buffer*>{
      own(position), own(velocity), own(connector_particles), own(connector_rest_length), own(connector_stiffness),
      own(connector_damping), own(connector_active), own(slot_force), own(element_power), &origin_position_array,
      &origin_velocity_array});
  radial_pass_.bind(std::vector<const Buffer*>{
      own(position), own(velocity), own(radial_particles), own(radial_rest_angle), own(radial_stiffness),
      own(radial_damping), own(radial_fade_length), own(radial_active), own(slot_force), own(element_power),
      &origin_position_array, &origin_velocity_array});
}

void DeviceForces::upload_model(const ClothModel& model) {
  const std::array<std::vector<std::byte>, array_count> contents = model_contents(model, precision_, terms_, path_);
  for (std::uint32_t a = 0; a < array_count; ++a) {
    if (!contents[a].empty()) upload(device_, arrays_[a], contents[a]);
  }
  model_revision_ = model.revision;
}

void DeviceForces::refresh(const ClothModel& model) {
  CLOTHSIM_ASSERT(model.particle_count() == particles_ && model.connector_count() == connectors_ &&
                      model.radial_count() == radials_,
                  "DeviceForces::refresh: the same particles and elements");
  upload_model(model);
}

void DeviceForces::record_element_passes(VkCommandBuffer commands, std::uint32_t power_slot) const {
  CLOTHSIM_ASSERT(path_ == DeviceForcePath::general, "DeviceForces: the element passes are the general path's");
  CLOTHSIM_ASSERT(power_slot < power_slots_, "DeviceForces: a power slot it holds");
  const std::uint32_t damped = (terms_ & kSpringDamping) != 0 ? 1u : 0u;
  const std::uint32_t power_base = power_slot * (connectors_ + radials_);
  const ElementPassConstants connector_constants{connectors_, damped, 0, power_base};
  const ElementPassConstants radial_constants{radials_, damped, 2 * connectors_, power_base + connectors_};
  connector_pass_.dispatch(commands, &connector_constants, connectors_);
  radial_pass_.dispatch(commands, &radial_constants, radials_);
}

void DeviceForces::record_forces(VkCommandBuffer commands) const {
  const GatherConstants gather_constants{particles_};
  const std::uint32_t elements = connectors_ + radials_;
  const SumConstants block_sums{elements, kReductionBlock, 0};
  const SumConstants total_sum{elements, kReductionBlock, 1};
  record_element_passes(commands, 0);
  gather_pass_.dispatch(commands, &gather_constants, particles_);
  sum_pass_.dispatch(commands, &block_sums, (elements + kReductionBlock - 1) / kReductionBlock);
  sum_pass_.dispatch(commands, &total_sum, 1);
}

double DeviceForces::evaluate(const ClothModel& model, std::span<const Vec3> position_in,
                              std::span<const Vec3> velocity_in, std::span<Vec3> force_out) {
  CLOTHSIM_ASSERT(path_ == DeviceForcePath::general, "DeviceForces::evaluate runs the general path");
  CLOTHSIM_ASSERT(model.revision == model_revision_ && model.particle_count() == particles_,
                  "DeviceForces: the model changed since it was uploaded (refresh() it)");
  CLOTHSIM_ASSERT(
      position_in.size() == particles_ && velocity_in.size() == particles_ && force_out.size() == particles_,
      "DeviceForces::evaluate: one position, velocity and force per particle");
  upload(device_, arrays_[position], vector_bytes(position_in, precision_));
  upload(device_, arrays_[velocity], vector_bytes(velocity_in, precision_));
  device_.submit([&](VkCommandBuffer commands) { record_forces(commands); });
  std::vector<std::byte> result(std::uint64_t{particles_} * 3 * real_size(precision_));
  download(device_, arrays_[force], result);
  const std::vector<Vec3> forces = vectors_from_bytes(result, precision_);
  std::copy(forces.begin(), forces.end(), force_out.begin());
  std::vector<std::byte> power(real_size(precision_));
  download(device_, arrays_[damping_power], power);
  return reals_from_bytes(power, precision_)[0];
}

}  // namespace clothsim::gpu
