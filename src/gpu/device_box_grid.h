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
#include "gpu/shaders/box_grid.h"

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
  std::uint32_t oversize_count() const { return oversize_count_; }

  // The arrays a query reads (box_grid_query.comp): the cell size, the extent, the entries, the
  // buckets' starts, the entries by bucket, the boxes kept aside.
  struct Arrays {
    const Buffer* grid_real;
    const Buffer* extent;
    const Buffer* entries;
    const Buffer* bucket_start;
    const Buffer* sorted;
    const Buffer* oversize;
  };
  Arrays arrays() const { return {&grid_real_, &extent_, &entries_, &bucket_start_, &sorted_, &oversize_}; }

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

// Queries of a built DeviceBoxGrid (shaders/box_grid_query.comp): every stored box that each query
// box overlaps, once, as (query, box) pairs in the order of the CPU's BoxGrid::for_each_overlap
// over the queries in turn; and the grid joined with itself, every overlapping pair of its boxes
// once, as (i, j), i < j, in the order of BoxGrid::for_each_pair over all the buckets.
class DeviceGridQuery {
 public:
  // For up to `capacity` queries, in `precision`'s Reals.
  DeviceGridQuery(Device& device, Precision precision, std::uint32_t capacity);

  // The pairs of the first `count` boxes of `queries` ([count][6] Reals) with the boxes `stored`
  // that `grid` was built of; with `exclude` ([stored][3] words), a stored box whose words name
  // the query is skipped (a triangle of which the particle is a corner). Returns how many. Two
  // submissions: the pairs counted and scanned, then written (their array sized from the count).
  std::uint32_t run(const DeviceBoxGrid& grid, const Buffer& stored, const Buffer& queries, std::uint32_t count,
                    const Buffer* exclude);
  // The pairs of `grid`'s boxes `stored` ([stored_count][6] Reals) that overlap; with `exclude`
  // ([stored][2] words), two boxes whose words share one are skipped (two edges with a particle in
  // common). Returns how many; the same two submissions.
  std::uint32_t join(const DeviceBoxGrid& grid, const Buffer& stored, std::uint32_t stored_count,
                     const Buffer* exclude);
  // Read back (tests): [pairs][2] of the last run() or join().
  std::vector<std::uint32_t> pairs() const;
  // The pairs on the device: at least 2 words a pair.
  const Buffer& pair_buffer() const { return pairs_; }

 private:
  // Counts for `invocations`, scanned, then the pairs written: the two submissions.
  std::uint32_t count_and_write(GridQueryConstants constants, std::uint32_t invocations,
                                const std::vector<const Buffer*>& inputs);

  Device& device_;
  std::uint32_t capacity_;
  std::uint32_t pair_count_ = 0;
  Buffer counts_, pairs_, no_exclude_;
  std::optional<PrefixScan> scan_;
  ComputePipeline pass_;
};

}  // namespace clothsim::gpu
