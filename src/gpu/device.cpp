#include "gpu/device.h"

#include <vector>

#include "gpu/gpu_error.h"

namespace clothsim::gpu {

std::string mebibytes(std::uint64_t bytes) {
  constexpr std::uint64_t kMiB = 1024 * 1024;
  return std::to_string((bytes + kMiB - 1) / kMiB) + " MiB";
}

namespace {

std::string device_name(const DeviceInfo& info) { return info.name + " (device " + std::to_string(info.index) + ")"; }

}  // namespace

Device::Device(DeviceOptions options) : instance_(InstanceOptions{options.validation}) {
  const std::vector<VkPhysicalDevice> devices = instance_.physical_devices();
  if (devices.empty()) throw GpuError("no Vulkan device: the Vulkan loader found no device (no driver installed?)");
  if (options.index >= devices.size()) {
    throw GpuError("no Vulkan device " + std::to_string(options.index) + " (there are " +
                   std::to_string(devices.size()) + "; 'clothsim devices' lists them)");
  }
  physical_device_ = devices[options.index];
  info_ = Instance::describe(physical_device_, options.index);
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(physical_device_, &properties);
  limits_ = properties.limits;
  vkGetPhysicalDeviceMemoryProperties(physical_device_, &memory_);

  std::uint32_t family_count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical_device_, &family_count, nullptr);
  std::vector<VkQueueFamilyProperties> families(family_count);
  vkGetPhysicalDeviceQueueFamilyProperties(physical_device_, &family_count, families.data());
  std::uint32_t family = family_count;
  for (std::uint32_t i = 0; i < family_count && family == family_count; ++i) {
    if ((families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) != 0) family = i;
  }
  if (family == family_count) throw GpuError(device_name(info_) + " has no compute queue");
  timestamp_valid_bits_ = families[family].timestampValidBits;

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queue{};
  queue.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  queue.queueFamilyIndex = family;
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  VkPhysicalDeviceFeatures features{};
  features.shaderFloat64 = info_.float64 ? VK_TRUE : VK_FALSE;
  VkDeviceCreateInfo create{};
  create.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  create.queueCreateInfoCount = 1;
  create.pQueueCreateInfos = &queue;
  create.pEnabledFeatures = &features;
  check(vkCreateDevice(physical_device_, &create, nullptr, &device_), "vkCreateDevice");
  vkGetDeviceQueue(device_, family, 0, &queue_);

  VkCommandPoolCreateInfo pool{};
  pool.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool.queueFamilyIndex = family;
  VkCommandBufferAllocateInfo allocate{};
  allocate.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocate.commandBufferCount = 1;
  VkFenceCreateInfo fence{};
  fence.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  try {
    check(vkCreateCommandPool(device_, &pool, nullptr, &command_pool_), "vkCreateCommandPool");
    allocate.commandPool = command_pool_;
    check(vkAllocateCommandBuffers(device_, &allocate, &command_buffer_), "vkAllocateCommandBuffers");
    check(vkCreateFence(device_, &fence, nullptr, &fence_), "vkCreateFence");
  } catch (...) {
    vkDestroyCommandPool(device_, command_pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
    throw;
  }
}

Device::~Device() {
  vkDeviceWaitIdle(device_);
  vkDestroyFence(device_, fence_, nullptr);
  vkDestroyCommandPool(device_, command_pool_, nullptr);  // frees its command buffers
  vkDestroyDevice(device_, nullptr);
}

void Device::require_memory(std::uint64_t bytes, const std::string& what) const {
  if (bytes > info_.device_local_bytes) {
    throw GpuError(what + " needs " + mebibytes(bytes) + " of device memory, " + device_name(info_) + " has " +
                   mebibytes(info_.device_local_bytes));
  }
}

void Device::require_precision(Precision precision) const {
  if (precision == Precision::float64 && !info_.float64) {
    throw GpuError(device_name(info_) + " does not support float64 (shaderFloat64); float32 runs on it");
  }
}

std::uint32_t Device::memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags properties) const {
  for (std::uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
    if ((type_bits & (1u << i)) != 0 && (memory_.memoryTypes[i].propertyFlags & properties) == properties) return i;
  }
  throw GpuError(device_name(info_) + " has no memory type for a buffer with properties " + std::to_string(properties));
}

void Device::submit(const std::function<void(VkCommandBuffer)>& record) {
  check(vkResetCommandBuffer(command_buffer_, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(command_buffer_, &begin), "vkBeginCommandBuffer");
  record(command_buffer_);
  check(vkEndCommandBuffer(command_buffer_), "vkEndCommandBuffer");
  run(command_buffer_);
}

VkCommandBuffer Device::record(const std::function<void(VkCommandBuffer)>& record) {
  VkCommandBufferAllocateInfo allocate{};
  allocate.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  allocate.commandPool = command_pool_;
  allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocate.commandBufferCount = 1;
  VkCommandBuffer commands = VK_NULL_HANDLE;
  check(vkAllocateCommandBuffers(device_, &allocate, &commands), "vkAllocateCommandBuffers");
  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  check(vkBeginCommandBuffer(commands, &begin), "vkBeginCommandBuffer");
  record(commands);
  check(vkEndCommandBuffer(commands), "vkEndCommandBuffer");
  return commands;
}

void Device::release(VkCommandBuffer commands) { vkFreeCommandBuffers(device_, command_pool_, 1, &commands); }

void Device::run(VkCommandBuffer commands) {
  VkSubmitInfo submit{};
  submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commands;
  check(vkQueueSubmit(queue_, 1, &submit, fence_), "vkQueueSubmit");
  check(vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  check(vkResetFences(device_, 1, &fence_), "vkResetFences");
}

}  // namespace clothsim::gpu
