#include "gpu/buffer.h"

#include <algorithm>
#include <cstring>
#include <optional>
#include <utility>

#include "gpu/gpu_error.h"

namespace clothsim::gpu {

Buffer::Buffer(Device& device, std::uint64_t bytes, Memory memory)
    : device_(device.handle()), bytes_(std::max<std::uint64_t>(bytes, 16)) {
  if (memory == Memory::device_local) device.require_memory(bytes_, "a buffer");
  VkBufferCreateInfo create{};
  create.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  create.size = bytes_;
  create.usage =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  create.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check(vkCreateBuffer(device_, &create, nullptr, &buffer_), "vkCreateBuffer");
  try {
    VkMemoryRequirements requirements{};
    vkGetBufferMemoryRequirements(device_, buffer_, &requirements);
    const VkMemoryPropertyFlags staging = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    VkMemoryAllocateInfo allocate{};
    allocate.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
    allocate.allocationSize = requirements.size;
    if (memory == Memory::device_local) {
      allocate.memoryTypeIndex = device.memory_type(requirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    } else {
      // Cached where the device has it: the host reads the read-backs, and on a discrete GPU
      // uncached host memory is write-combined, slow to read (a 1024 x 1024 sheet's state took
      // tens of milliseconds per frame on an H200's host; docs/performance.md).
      try {
        allocate.memoryTypeIndex =
            device.memory_type(requirements.memoryTypeBits, staging | VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
      } catch (const GpuError&) {
        allocate.memoryTypeIndex = device.memory_type(requirements.memoryTypeBits, staging);
      }
    }
    check(vkAllocateMemory(device_, &allocate, nullptr, &memory_), "vkAllocateMemory");
    check(vkBindBufferMemory(device_, buffer_, memory_, 0), "vkBindBufferMemory");
    if (memory == Memory::host_visible) {
      void* pointer = nullptr;
      check(vkMapMemory(device_, memory_, 0, VK_WHOLE_SIZE, 0, &pointer), "vkMapMemory");
      mapped_ = static_cast<std::byte*>(pointer);
    }
  } catch (...) {
    vkFreeMemory(device_, memory_, nullptr);
    vkDestroyBuffer(device_, buffer_, nullptr);
    throw;
  }
}

Buffer::Buffer(Buffer&& other) noexcept
    : device_(other.device_),
      buffer_(std::exchange(other.buffer_, VK_NULL_HANDLE)),
      memory_(std::exchange(other.memory_, VK_NULL_HANDLE)),
      bytes_(other.bytes_),
      mapped_(std::exchange(other.mapped_, nullptr)) {}

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  std::swap(device_, other.device_);
  std::swap(buffer_, other.buffer_);
  std::swap(memory_, other.memory_);
  std::swap(bytes_, other.bytes_);
  std::swap(mapped_, other.mapped_);
  return *this;  // `other` frees what this held
}

Buffer::~Buffer() {
  if (buffer_ == VK_NULL_HANDLE) return;
  vkDestroyBuffer(device_, buffer_, nullptr);
  vkFreeMemory(device_, memory_, nullptr);  // unmaps a mapped allocation
}

namespace {

void memory_barrier(VkCommandBuffer commands, VkPipelineStageFlags from_stage, VkAccessFlags from_access,
                    VkPipelineStageFlags to_stage, VkAccessFlags to_access) {
  VkMemoryBarrier barrier{};
  barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  barrier.srcAccessMask = from_access;
  barrier.dstAccessMask = to_access;
  vkCmdPipelineBarrier(commands, from_stage, to_stage, 0, 1, &barrier, 0, nullptr, 0, nullptr);
}

}  // namespace

void compute_write_barrier(VkCommandBuffer commands) {
  memory_barrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT);
}

void upload(Device& device, Buffer& destination, std::span<const std::byte> source, const Buffer* staging) {
  if (source.size() > destination.bytes()) throw GpuError("upload: more bytes than the buffer holds");
  if (source.empty()) return;
  std::optional<Buffer> own;
  if (staging == nullptr || staging->bytes() < source.size()) {
    staging = &own.emplace(device, source.size(), Memory::host_visible);
  }
  std::memcpy(staging->mapped(), source.data(), source.size());
  device.submit([&](VkCommandBuffer commands) {
    const VkBufferCopy region{0, 0, source.size()};
    vkCmdCopyBuffer(commands, staging->handle(), destination.handle(), 1, &region);
    memory_barrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  });
}

void record_readback(VkCommandBuffer commands, const Buffer& source, const Buffer& destination, std::uint64_t bytes,
                     std::uint64_t destination_offset) {
  const VkBufferCopy region{0, destination_offset, bytes};
  vkCmdCopyBuffer(commands, source.handle(), destination.handle(), 1, &region);
  memory_barrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                 VK_ACCESS_HOST_READ_BIT);
}

void record_upload(VkCommandBuffer commands, const Buffer& source, const Buffer& destination, std::uint64_t bytes,
                   std::uint64_t source_offset) {
  const VkBufferCopy region{source_offset, 0, bytes};
  vkCmdCopyBuffer(commands, source.handle(), destination.handle(), 1, &region);
  memory_barrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

void record_upload(VkCommandBuffer commands, const Buffer& source, const Buffer& destination,
                   std::span<const VkBufferCopy> regions) {
  if (regions.empty()) return;
  vkCmdCopyBuffer(commands, source.handle(), destination.handle(), static_cast<std::uint32_t>(regions.size()),
                  regions.data());
  memory_barrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

void record_copy(VkCommandBuffer commands, const Buffer& source, const Buffer& destination, std::uint64_t bytes) {
  compute_write_barrier(commands);
  record_upload(commands, source, destination, bytes);
}

void record_zero(VkCommandBuffer commands, const Buffer& destination, std::uint64_t bytes) {
  compute_write_barrier(commands);
  vkCmdFillBuffer(commands, destination.handle(), 0, bytes, 0u);
  memory_barrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

void download(Device& device, const Buffer& source, std::span<std::byte> destination) {
  if (destination.size() > source.bytes()) throw GpuError("download: more bytes than the buffer holds");
  if (destination.empty()) return;
  Buffer staging(device, destination.size(), Memory::host_visible);
  device.submit([&](VkCommandBuffer commands) { record_readback(commands, source, staging, destination.size()); });
  std::memcpy(destination.data(), staging.mapped(), destination.size());
}

}  // namespace clothsim::gpu
