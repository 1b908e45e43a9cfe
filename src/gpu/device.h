// One Vulkan device opened for compute: the logical device, one compute queue, one command
// buffer with its fence, and the device's memory types. Work is recorded and submitted through
// submit(), which waits for it: the element passes and the tests need nothing more yet. The
// backend's step (docs/gpu.md, "Not done yet") will record a whole step into one submission.
//
// Devices are numbered as vkEnumeratePhysicalDevices lists them, the numbers `clothsim devices`
// prints. The float64 shaders need shaderFloat64, which the device enables when it has it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include <vulkan/vulkan.h>

#include "core/precision.h"
#include "core/stage_passes.h"
#include "gpu/instance.h"

namespace clothsim::gpu {

// The precision of the device's arithmetic (core/precision.h): the names of --precision.
using clothsim::Precision;

struct DeviceOptions {
  std::uint32_t index = 0;                 // which device of Instance::devices()
  bool validation = kValidationByDefault;  // validation layers, if installed (InstanceOptions::validation)
};

// Which device an integrator runs on, and in which precision.
struct DeviceSelection {
  std::uint32_t index = 0;  // the device, as `clothsim devices` numbers it
  Precision precision = Precision::float32;
  bool validation = kValidationByDefault;  // the validation layers, where installed
  // The explicit methods' stages on a lattice sheet: three passes a stage, one, or several stages
  // chained in a pass (core/stage_passes.h); the same bits. Unset: chained on a GPU, split on a
  // CPU device such as lavapipe, where the one pass's extra arithmetic costs more than the memory
  // it saves (docs/gpu.md, "One pass per stage").
  std::optional<StagePasses> stage_passes = std::nullopt;
};

class Device {
 public:
  // Throws GpuError: "no Vulkan device" (none at all), "no Vulkan device N (there are M)",
  // "device N (<name>) has no compute queue", or a failed call.
  explicit Device(DeviceOptions options = {});
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  const DeviceInfo& info() const { return info_; }
  VkDevice handle() const { return device_; }
  const Instance& instance() const { return instance_; }
  const VkPhysicalDeviceLimits& limits() const { return limits_; }
  // The bits of a timestamp its compute queue writes (0: no timestamps there).
  std::uint32_t timestamp_valid_bits() const { return timestamp_valid_bits_; }

  // Throws GpuError "<what> needs X MiB of device memory, <device> has Y MiB" when `bytes` is more
  // than the device-local memory. A check before anything is allocated or written.
  void require_memory(std::uint64_t bytes, const std::string& what) const;
  // Throws GpuError "... does not support float64 (shaderFloat64)" for float64 on such a device.
  void require_precision(Precision precision) const;

  // The index of a memory type allowed by `type_bits` with all of `properties`, or throws.
  std::uint32_t memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags properties) const;

  // Records commands with `record` into the device's command buffer, submits it and waits for it.
  void submit(const std::function<void(VkCommandBuffer)>& record);
  // Records commands into a command buffer of their own, kept for submitting many times with
  // run() (a device step's fixed sequence of passes); freed with the device.
  VkCommandBuffer record(const std::function<void(VkCommandBuffer)>& record);
  // Submits a command buffer from record() and waits for it.
  void run(VkCommandBuffer commands);
  // Frees a command buffer from record() before the device goes.
  void release(VkCommandBuffer commands);

 private:
  Instance instance_;
  DeviceInfo info_;
  VkPhysicalDevice physical_device_ = VK_NULL_HANDLE;
  VkPhysicalDeviceLimits limits_{};
  std::uint32_t timestamp_valid_bits_ = 0;
  VkPhysicalDeviceMemoryProperties memory_{};
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkCommandPool command_pool_ = VK_NULL_HANDLE;
  VkCommandBuffer command_buffer_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
};

// "812 MiB": bytes in MiB, rounded up.
std::string mebibytes(std::uint64_t bytes);

}  // namespace clothsim::gpu
