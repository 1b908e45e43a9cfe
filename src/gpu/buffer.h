// Storage buffers on the device, and copies to and from them through host-visible staging
// buffers. A Buffer owns its VkBuffer and its own memory allocation (a handful of buffers per
// scene: the model's arrays and the state; no suballocator is needed at that count).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include <vulkan/vulkan.h>

#include "gpu/device.h"

namespace clothsim::gpu {

enum class Memory {
  device_local,  // where the shaders read and write; reached by the host only through copies
  host_visible,  // staging: mapped for the host's whole lifetime of the buffer, coherent, and cached
                 // where the device offers it (for the read-backs the host reads)
};

class Buffer {
 public:
  // A storage buffer of `bytes` (at least 16) usable as a copy source and destination.
  Buffer(Device& device, std::uint64_t bytes, Memory memory);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  std::uint64_t bytes() const { return bytes_; }
  std::byte* mapped() const { return mapped_; }  // host_visible only, else null

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  std::uint64_t bytes_ = 0;
  std::byte* mapped_ = nullptr;
};

// Host bytes into a device-local buffer (from its start), and back; each one submission that
// waits. The barriers make the copy visible to later compute shaders and a shader's writes
// visible to the copy back. The copy goes through a staging buffer allocated for it, or for an
// upload through `staging` (host-visible, at least the bytes): what goes up again and again (a
// step's control words, anchor paths, collider rows) then allocates nothing.
void upload(Device& device, Buffer& destination, std::span<const std::byte> source, const Buffer* staging = nullptr);
void download(Device& device, const Buffer& source, std::span<std::byte> destination);

// Records a copy of `bytes` from the start of `source` into `destination` (a host_visible buffer)
// at `destination_offset`,
// made visible to the host once the submission's fence signals: a submission's results read
// back without a submission of their own.
void record_readback(VkCommandBuffer commands, const Buffer& source, const Buffer& destination, std::uint64_t bytes,
                     std::uint64_t destination_offset = 0);

// Records a copy of `bytes` from `source` (a host_visible buffer the host wrote before the
// submission) at `source_offset` into the start of `destination`, made visible to the compute
// shaders after it: a submission's inputs written without a submission of their own.
void record_upload(VkCommandBuffer commands, const Buffer& source, const Buffer& destination, std::uint64_t bytes,
                   std::uint64_t source_offset = 0);

// The same for several regions of `source` into places of `destination` (VkBufferCopy: source
// offset, destination offset, bytes), in one copy command.
void record_upload(VkCommandBuffer commands, const Buffer& source, const Buffer& destination,
                   std::span<const VkBufferCopy> regions);

// Records a copy of `bytes` from the start of one device buffer into the start of another, after
// the compute passes before it and visible to those after it.
void record_copy(VkCommandBuffer commands, const Buffer& source, const Buffer& destination, std::uint64_t bytes);

// Records zeros into the first `bytes` (a multiple of 4) of a device buffer, after the compute
// passes before it and visible to those after it: counters cleared without a submission of their own.
void record_zero(VkCommandBuffer commands, const Buffer& destination, std::uint64_t bytes);

// The barrier between a compute pass and whatever reads its output next: a later pass or a copy.
void compute_write_barrier(VkCommandBuffer commands);

}  // namespace clothsim::gpu
