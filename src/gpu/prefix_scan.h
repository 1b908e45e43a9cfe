// An exclusive prefix sum of unsigned 32-bit counts on the device (shaders/prefix_scan.comp): the
// step of every compaction and counting sort on the device, where each item first counts what it
// will write and then writes it at the sum of the counts before it, so that the output's order is
// the items' order whatever the scheduling (self-collision's candidates and grid, docs/gpu.md).
#pragma once

#include <cstdint>

#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "gpu/compute_pipeline.h"
#include "gpu/device.h"

namespace clothsim::gpu {

class PrefixScan {
 public:
  // For up to `capacity` values.
  PrefixScan(Device& device, std::uint32_t capacity);

  // Room for `capacity` values, if it had less (then bind() again).
  void reserve(std::uint32_t capacity);
  // The values the passes scan: at least capacity() uint32s (again whenever the buffer is replaced).
  void bind(const Buffer& values);
  // Records the passes over the first `count` values (at most capacity()): each becomes the sum of
  // those before it, and the total is written to word blocks_for(count) of block_sums().
  void record(VkCommandBuffer commands, std::uint32_t count) const;

  // The total of the last record()'s `count` values, read back after its submission.
  std::uint32_t total(std::uint32_t count) const;

  std::uint32_t capacity() const { return capacity_; }
  const Buffer& block_sums() const { return block_sums_; }
  static std::uint32_t blocks_for(std::uint32_t count);

 private:
  Device& device_;
  std::uint32_t capacity_;
  Buffer block_sums_;  // [blocks_for(capacity) + 1]
  ComputePipeline pass_;
};

}  // namespace clothsim::gpu
