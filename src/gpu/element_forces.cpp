#include "gpu/element_forces.h"

#include <cstring>
#include <string>

#include "gpu/embedded_shaders.h"
#include "gpu/gpu_error.h"
#include "gpu/shaders/element_pass.h"

namespace clothsim::gpu {
namespace {

constexpr std::uint32_t kBindings = 8;  // 6 inputs, 2 outputs: the shaders' binding list

// Reals in the device's precision: doubles as they are (the CPU's layout uploaded unchanged),
// or each rounded to float.
std::vector<std::byte> real_bytes(std::span<const double> values, Precision precision) {
  std::vector<std::byte> bytes(values.size() * real_size(precision));
  if (precision == Precision::float64) {
    std::memcpy(bytes.data(), values.data(), bytes.size());
  } else {
    for (std::size_t i = 0; i < values.size(); ++i) {
      const float value = static_cast<float>(values[i]);
      std::memcpy(bytes.data() + 4 * i, &value, 4);
    }
  }
  return bytes;
}

std::vector<std::byte> vector_bytes(std::span<const Vec3> vectors, Precision precision) {
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 is three packed doubles");
  if (vectors.empty()) return {};
  return real_bytes(std::span<const double>(&vectors.data()->x, 3 * vectors.size()), precision);
}

template <std::size_t N>
std::vector<std::byte> index_bytes(std::span<const std::array<std::uint32_t, N>> indices) {
  std::vector<std::byte> bytes(indices.size_bytes());
  std::memcpy(bytes.data(), indices.data(), bytes.size());
  return bytes;
}

std::vector<double> reals_from_bytes(std::span<const std::byte> bytes, Precision precision) {
  std::vector<double> values(bytes.size() / real_size(precision));
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (precision == Precision::float64) {
      std::memcpy(&values[i], bytes.data() + 8 * i, 8);
    } else {
      float value = 0.0f;
      std::memcpy(&value, bytes.data() + 4 * i, 4);
      values[i] = value;
    }
  }
  return values;
}

std::uint32_t element_count(std::size_t count, bool arrays_agree, const char* what) {
  if (!arrays_agree) throw GpuError(std::string(what) + ": the element arrays differ in length");
  if (count > UINT32_MAX / 9) throw GpuError(std::string(what) + ": too many elements for 32-bit slot indices");
  return static_cast<std::uint32_t>(count);
}

Device& with_precision(Device& device, Precision precision) {
  device.require_precision(precision);
  return device;
}

}  // namespace

ElementForcePasses::ElementForcePasses(Device& device, Precision precision)
    : device_(with_precision(device, precision)),
      precision_(precision),
      connector_pass_(device, embedded_shader(shader_variant("accumulate_connector_springs", precision)), kBindings,
                      sizeof(ElementPassConstants)),
      radial_pass_(device, embedded_shader(shader_variant("accumulate_radial_springs", precision)), kBindings,
                   sizeof(ElementPassConstants)) {}

ElementForces ElementForcePasses::run(ComputePipeline& pipeline, std::span<const std::vector<std::byte>> inputs,
                                      std::uint32_t count, std::uint32_t slots_per_element, bool damped) {
  const std::size_t real = real_size(precision_);
  const std::uint64_t slot_bytes = std::uint64_t{count} * slots_per_element * 3 * real;
  const std::uint64_t power_bytes = std::uint64_t{count} * real;
  std::uint64_t total = slot_bytes + power_bytes;
  for (const std::vector<std::byte>& input : inputs) total += input.size();
  device_.require_memory(total, "the element force pass");

  std::vector<Buffer> buffers;
  buffers.reserve(kBindings);
  for (const std::vector<std::byte>& input : inputs) {
    buffers.emplace_back(device_, input.size(), Memory::device_local);
    upload(device_, buffers.back(), input);
  }
  buffers.emplace_back(device_, slot_bytes, Memory::device_local);
  buffers.emplace_back(device_, power_bytes, Memory::device_local);
  std::vector<const Buffer*> bound;
  for (const Buffer& buffer : buffers) bound.push_back(&buffer);
  pipeline.bind(bound);

  const ElementPassConstants constants{count, damped ? 1u : 0u};
  device_.submit([&](VkCommandBuffer commands) { pipeline.dispatch(commands, &constants, count); });

  std::vector<std::byte> slot_result(slot_bytes);
  std::vector<std::byte> power_result(power_bytes);
  download(device_, buffers[kBindings - 2], slot_result);
  download(device_, buffers[kBindings - 1], power_result);
  const std::vector<double> slot_reals = reals_from_bytes(slot_result, precision_);
  ElementForces forces;
  forces.slot_force.resize(slot_reals.size() / 3);
  for (std::size_t i = 0; i < forces.slot_force.size(); ++i) {
    forces.slot_force[i] = {slot_reals[3 * i], slot_reals[3 * i + 1], slot_reals[3 * i + 2]};
  }
  forces.element_power = reals_from_bytes(power_result, precision_);
  return forces;
}

ElementForces ElementForcePasses::accumulate_connector_springs(const ConnectorSpringArrays& arrays, bool damped) {
  const std::size_t n = arrays.connector_particles.size();
  const std::uint32_t count =
      element_count(n,
                    arrays.connector_rest_length.size() == n && arrays.connector_stiffness.size() == n &&
                        arrays.connector_damping.size() == n && arrays.position.size() == arrays.velocity.size(),
                    "accumulate_connector_springs");
  const std::vector<std::byte> inputs[] = {vector_bytes(arrays.position, precision_),
                                           vector_bytes(arrays.velocity, precision_),
                                           index_bytes(arrays.connector_particles),
                                           real_bytes(arrays.connector_rest_length, precision_),
                                           real_bytes(arrays.connector_stiffness, precision_),
                                           real_bytes(arrays.connector_damping, precision_)};
  return run(connector_pass_, inputs, count, 2, damped);
}

ElementForces ElementForcePasses::accumulate_radial_springs(const RadialSpringArrays& arrays, bool damped) {
  const std::size_t n = arrays.radial_particles.size();
  const std::uint32_t count =
      element_count(n,
                    arrays.radial_rest_angle.size() == n && arrays.radial_stiffness.size() == n &&
                        arrays.radial_damping.size() == n && arrays.position.size() == arrays.velocity.size(),
                    "accumulate_radial_springs");
  const std::vector<std::byte> inputs[] = {vector_bytes(arrays.position, precision_),
                                           vector_bytes(arrays.velocity, precision_),
                                           index_bytes(arrays.radial_particles),
                                           real_bytes(arrays.radial_rest_angle, precision_),
                                           real_bytes(arrays.radial_stiffness, precision_),
                                           real_bytes(arrays.radial_damping, precision_)};
  return run(radial_pass_, inputs, count, 3, damped);
}

}  // namespace clothsim::gpu
