// Errors of the Vulkan layer: no loader or device, a device without a needed feature, a scene
// larger than the device's memory, a Vulkan call that failed. Each message names what failed and,
// for a failed call, the call and its VkResult, so that it reads on its own:
//   "no Vulkan device: vkCreateInstance failed: VK_ERROR_INCOMPATIBLE_DRIVER (no driver installed?)"
//   "the scene needs 812 MiB of device memory, llvmpipe (device 0) has 512 MiB"
// Thrown when a device is opened or a buffer made, never from inside a dispatch.
#pragma once

#include <stdexcept>
#include <string>

namespace clothsim::gpu {

class GpuError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace clothsim::gpu
