// The broad phase's hashed grid of boxes on the device (shaders/box_grid.comp), the first stage of
// self-collision's candidates on the device (docs/gpu.md, "Not done yet"): built as the CPU's
// BoxGrid (collision/box_grid.h) builds it, so that for the same boxes and cell size each bucket
// holds the same entries in the same order, and the same boxes are kept aside.
//
// build() is two submissions: the boxes' cells counted and scanned, then, with the entries'
// count read back to size the buckets as the CPU does (twice the entries, a power of two, at least
// 16), the entries written, the buckets counted, scanned, filled and sorted.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/precision.h"
#include "gpu/buffer.h"
#include "gpu/compute_pipeline.h"
#include "gpu/device.h"
#include "gpu/prefix_scan.h"

namespace clothsim::gpu {

class DeviceBoxGrid {
 public:
  // For up to `capacity` boxes, in `precision`'s Reals.
  DeviceBoxGrid(Device& device, Precision precision, std::uint32_t capacity);

  // The grid of the first `count` boxes of `boxes` ([count][6] Reals: the low corner, then the
  // high one), with cubic cells of `cell_size` m.
  void build(const Buffer& boxes, std::uint32_t count, double cell_size);

  std::uint32_t entry_count() const { return entry_count_; }
  std::uint32_t bucket_count() const { return bucket_mask_ + 1; }

  // Read back (tests): each bucket's first entry and, last, the entries' count; the entries in
  // bucket order, kEntryWords each (box_grid.h); the boxes kept aside, ascending; the entered
  // boxes' lowest and highest cells.
  std::vector<std::uint32_t> bucket_starts() const;
  std::vector<std::uint32_t> entries_by_bucket() const;
  std::vector<std::uint32_t> oversize() const;
  std::array<std::int32_t, 6> extent() const;

 private:
  void bind();

  Device& device_;
  Precision precision_;
  std::uint32_t capacity_;
  std::uint32_t entry_count_ = 0;
  std::uint32_t oversize_count_ = 0;
  std::uint32_t bucket_mask_ = 15;
  const Buffer* boxes_ = nullptr;
  Buffer grid_real_, low_cell_, cells_of_, oversize_flag_, oversize_, extent_, entries_, bucket_start_, fill_, sorted_;
  PrefixScan cells_scan_, oversize_scan_;
  std::optional<PrefixScan> bucket_scan_;
  ComputePipeline pass_;
};

}  // namespace clothsim::gpu
