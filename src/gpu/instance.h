// The Vulkan instance and what it can see: the physical devices, described for
// `clothsim devices` and for choosing one.
//
// Validation layers (VK_LAYER_KHRONOS_validation, Debian's vulkan-validationlayers) are enabled
// when asked for and installed, never required: debug builds and the tests ask for them. Their
// messages go to stderr and the errors among them are counted (validation_errors()), so a test
// can fail on any. Rejected: vulkan.hpp (its exceptions and generated wrappers are a large
// header for the handful of calls made here; plain C calls with one check() read as well).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace clothsim::gpu {

// Throws GpuError "<call> failed: <VkResult name>" unless result is VK_SUCCESS.
void check(VkResult result, const char* call);
const char* result_name(VkResult result);

struct DeviceInfo {
  std::uint32_t index = 0;               // position in vkEnumeratePhysicalDevices, the N of --device N
  std::string name;                      // "llvmpipe (LLVM 15.0.6, 256 bits)", "NVIDIA H100 80GB HBM3"
  std::string type;                      // "discrete", "integrated", "virtual", "cpu", "other"
  std::string driver;                    // driver name and version text: "llvmpipe Mesa 22.3.6 (LLVM 15.0.6)"
  std::string api_version;               // "1.3.230"
  std::uint64_t device_local_bytes = 0;  // the largest device-local memory heap, bytes
  bool float64 = false;                  // shaderFloat64: the float64 shaders can run
};

// Debug builds (without NDEBUG) enable the validation layers by default; release builds only
// when asked, as the tests do.
#if defined(NDEBUG)
inline constexpr bool kValidationByDefault = false;
#else
inline constexpr bool kValidationByDefault = true;
#endif

struct InstanceOptions {
  bool validation = kValidationByDefault;  // enable the validation layers if they are installed
};

class Instance {
 public:
  // Throws GpuError "no Vulkan device: ..." when there is no loader driver to create one with.
  explicit Instance(InstanceOptions options = {});
  ~Instance();
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;

  VkInstance handle() const { return instance_; }
  bool validation_enabled() const { return messenger_ != VK_NULL_HANDLE; }
  // Validation errors reported so far (0 without the layers).
  std::uint64_t validation_errors() const;

  std::vector<VkPhysicalDevice> physical_devices() const;
  std::vector<DeviceInfo> devices() const;
  static DeviceInfo describe(VkPhysicalDevice device, std::uint32_t index);

 private:
  struct Messages;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  std::unique_ptr<Messages> messages_;  // the messenger's user data; its address stays put
};

}  // namespace clothsim::gpu
