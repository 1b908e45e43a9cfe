#include "gpu/element_forces.h"

#include <cstring>
#include <string>

#include "gpu/gpu_error.h"
#include "gpu/real_arrays.h"
#include "gpu/shaders/element_pass.h"

namespace clothsim::gpu {
namespace {

// The shaders' binding lists: the inputs, the active flags, 2 outputs, then the state the stage
// arrays are offsets from in float32 (shaders/stage_offsets.glsl): zeros here, so that the
// positions and velocities are read as they are.
constexpr std::uint32_t kConnectorBindings = 11;
constexpr std::uint32_t kRadialBindings = 12;

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
      connector_pass_(shader_pipeline(device, "accumulate_connector_springs", precision, kConnectorBindings,
                                      sizeof(ElementPassConstants))),
      radial_pass_(shader_pipeline(device, "accumulate_radial_springs", precision, kRadialBindings,
                                   sizeof(ElementPassConstants))) {}

ElementForces ElementForcePasses::run(ComputePipeline& pipeline, std::span<const std::vector<std::byte>> inputs,
                                      std::uint32_t count, std::uint32_t slots_per_element, bool damped) {
  const std::size_t real = real_size(precision_);
  const std::uint64_t slot_bytes = std::uint64_t{count} * slots_per_element * 3 * real;
  const std::uint64_t power_bytes = std::uint64_t{count} * real;
  std::uint64_t total = slot_bytes + power_bytes;
  for (const std::vector<std::byte>& input : inputs) total += input.size();
  total += std::uint64_t{count} * 4 + 2 * inputs[0].size();  // the active flags, the zero origins
  device_.require_memory(total, "the element force pass");

  const std::size_t bindings = inputs.size() + 5;
  std::vector<Buffer> buffers;
  buffers.reserve(bindings);
  for (const std::vector<std::byte>& input : inputs) {
    buffers.emplace_back(device_, input.size(), Memory::device_local);
    upload(device_, buffers.back(), input);
  }
  // Every element active: the arrays here have no broken springs and no term switched off.
  const std::vector<std::uint32_t> active(count, 1u);
  buffers.emplace_back(device_, active.size() * 4, Memory::device_local);
  upload(device_, buffers.back(), std::as_bytes(std::span(active)));
  buffers.emplace_back(device_, slot_bytes, Memory::device_local);
  buffers.emplace_back(device_, power_bytes, Memory::device_local);
  const std::vector<std::byte> zeros(inputs[0].size());  // as many as the positions
  for (int origin = 0; origin < 2; ++origin) {
    buffers.emplace_back(device_, zeros.size(), Memory::device_local);
    upload(device_, buffers.back(), zeros);
  }
  std::vector<const Buffer*> bound;
  for (const Buffer& buffer : buffers) bound.push_back(&buffer);
  pipeline.bind(bound);

  const ElementPassConstants constants{count, damped ? 1u : 0u, 0, 0};
  device_.submit([&](VkCommandBuffer commands) { pipeline.dispatch(commands, &constants, count); });

  std::vector<std::byte> slot_result(slot_bytes);
  std::vector<std::byte> power_result(power_bytes);
  download(device_, buffers[inputs.size() + 1], slot_result);
  download(device_, buffers[inputs.size() + 2], power_result);
  ElementForces forces;
  forces.slot_force = vectors_from_bytes(slot_result, precision_);
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
                        arrays.radial_damping.size() == n && arrays.radial_fade_length.size() == 2 * n &&
                        arrays.position.size() == arrays.velocity.size(),
                    "accumulate_radial_springs");
  const std::vector<std::byte> inputs[] = {vector_bytes(arrays.position, precision_),
                                           vector_bytes(arrays.velocity, precision_),
                                           index_bytes(arrays.radial_particles),
                                           real_bytes(arrays.radial_rest_angle, precision_),
                                           real_bytes(arrays.radial_stiffness, precision_),
                                           real_bytes(arrays.radial_damping, precision_),
                                           real_bytes(arrays.radial_fade_length, precision_)};
  return run(radial_pass_, inputs, count, 3, damped);
}

}  // namespace clothsim::gpu
