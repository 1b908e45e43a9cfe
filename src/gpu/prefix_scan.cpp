#include "gpu/prefix_scan.h"

#include <array>
#include <span>
#include <vector>

#include "core/assert.h"
#include "gpu/shaders/prefix_scan.h"

namespace clothsim::gpu {

std::uint32_t PrefixScan::blocks_for(std::uint32_t count) { return (count + kScanWorkgroup - 1) / kScanWorkgroup; }

PrefixScan::PrefixScan(Device& device, std::uint32_t capacity)
    : device_(device),
      capacity_(capacity),
      block_sums_(device, (std::uint64_t{blocks_for(capacity)} + 1) * sizeof(std::uint32_t), Memory::device_local),
      // The shader reads no Reals: either precision's variant is the same program.
      pass_(shader_pipeline(device, "prefix_scan", Precision::float32, 2, sizeof(ScanPassConstants), kScanWorkgroup)) {}

void PrefixScan::reserve(std::uint32_t capacity) {
  if (capacity <= capacity_) return;
  capacity_ = capacity;
  block_sums_ =
      Buffer(device_, (std::uint64_t{blocks_for(capacity)} + 1) * sizeof(std::uint32_t), Memory::device_local);
}

void PrefixScan::bind(const Buffer& values) {
  CLOTHSIM_ASSERT(values.bytes() >= std::uint64_t{capacity_} * sizeof(std::uint32_t), "the values fill the capacity");
  const std::array<const Buffer*, 2> buffers{&values, &block_sums_};
  pass_.bind(buffers);
}

std::uint32_t PrefixScan::total(std::uint32_t count) const {
  // The blocks' sums up to the total: the download reads from the buffer's start.
  std::vector<std::uint32_t> sums(blocks_for(count) + 1);
  download(device_, block_sums_, std::as_writable_bytes(std::span(sums)));
  return sums.back();
}

void PrefixScan::record(VkCommandBuffer commands, std::uint32_t count) const {
  CLOTHSIM_ASSERT(count <= capacity_, "at most the capacity");
  const std::uint32_t blocks = blocks_for(count);
  const ScanPassConstants blocks_pass{kScanBlocks, count, blocks};
  if (count > 0) pass_.dispatch(commands, &blocks_pass, count);
  const ScanPassConstants sums_pass{kScanBlockSums, count, blocks};
  pass_.dispatch(commands, &sums_pass, kScanWorkgroup);  // writes the total, 0 for no values
  const ScanPassConstants add_pass{kScanAdd, count, blocks};
  if (count > 0) pass_.dispatch(commands, &add_pass, count);
}

}  // namespace clothsim::gpu
