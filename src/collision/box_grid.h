// The broad phase of self-collision: which axis-aligned boxes overlap, in time linear in their
// number (collision/self_contacts.h).
//
// A uniform grid, hashed. Each stored box is entered in every cell it overlaps, and a query visits
// the cells its own box overlaps; a pair of overlapping boxes meets in every cell their
// intersection overlaps, and is reported only in the one holding the intersection's lowest corner
// (the larger of the two lowest corners), so exactly once, even where two cells share a hash
// bucket. The cell size is the mean extent of the stored boxes: a lattice's triangles and edges,
// near equal in size, enter about 2 x 2 x 1 cells each and a particle's small box visits 1 or 2.
// A box more than kOversize cells across on some axis (a piece of sheet flung far in one step)
// is not entered but kept aside and tested against every query, so that one outlier neither
// makes every cell large (which would make the search quadratic) nor enters millions of cells. Cells
// are hashed into a table of about twice as many buckets as entries, so the memory is linear in
// the boxes wherever they are, and a bucket's entries are kept in box index order (a counting
// sort), so every query reports in the same order for any thread count.
//
// Rejected: entering each box once, by its lowest corner, with cells as large as the largest box
// (a query must then visit 27 cells, most of them empty: 5 times slower on a draped sheet); a
// sort-and-sweep along one axis (a sheet lying flat puts all of it in one slab of that axis); a
// bounding-volume hierarchy (rebuilt or refitted every step, with a worse constant for boxes of
// near-equal size).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/vec3.h"

namespace clothsim {

struct Box {
  Vec3 low;
  Vec3 high;
};

inline bool overlap(const Box& a, const Box& b) {
  return a.low.x <= b.high.x && b.low.x <= a.high.x && a.low.y <= b.high.y && b.low.y <= a.high.y &&
         a.low.z <= b.high.z && b.low.z <= a.high.z;
}

class BoxGrid {
 public:
  // Enters `boxes` (kept by reference: they must outlive the queries and stay unchanged), over
  // `threads`; the grid is the same for any thread count.
  void build(std::span<const Box> boxes, int threads = 1);

  // Calls visit(j) for every stored box j that overlaps `query`, each once.
  template <typename Visit>
  void for_each_overlap(const Box& query, Visit&& visit) const {
    if (boxes_.empty()) return;
    const Cell low = cell_of(query.low);
    // A large query visits at most the cells of the stored boxes' range.
    const Cell query_high = cell_of(query.high);
    const Cell high = {std::min(query_high[0], extent_high_[0]), std::min(query_high[1], extent_high_[1]),
                       std::min(query_high[2], extent_high_[2])};
    for (std::int64_t x = std::max(low[0], extent_low_[0]); x <= high[0]; ++x) {
      for (std::int64_t y = std::max(low[1], extent_low_[1]); y <= high[1]; ++y) {
        for (std::int64_t z = std::max(low[2], extent_low_[2]); z <= high[2]; ++z) {
          const std::size_t bucket = bucket_of({x, y, z});
          for (std::uint32_t k = bucket_start_[bucket]; k < bucket_start_[bucket + 1]; ++k) {
            const Entry& entry = entries_[k];
            if (entry.cell[0] != x || entry.cell[1] != y || entry.cell[2] != z) continue;
            // Reported in the cell holding the intersection's lowest corner only; the cell of the
            // larger of two coordinates is the larger of their cells, and both boxes' lowest cells
            // are at most this one, so along each axis one of them must be this cell's.
            const unsigned lowest = entry.lowest | (low[0] == x ? 1u : 0u) | (low[1] == y ? 2u : 0u) |
                                    (low[2] == z ? 4u : 0u);
            if (lowest == kEveryAxis && overlap(boxes_[entry.box], query)) visit(entry.box);
          }
        }
      }
    }
    for (std::uint32_t j : oversize_) {
      if (overlap(boxes_[j], query)) visit(j);
    }
  }

  // Calls visit(i, j), i < j, for every pair of stored boxes that overlap, each once, taking the
  // buckets [first, last): the grid joined with itself. Each pair is met once per cell both enter
  // (not twice, as querying every stored box would), and reported in one. The kept-aside boxes
  // are paired with every box by the bucket range that starts at 0.
  template <typename Visit>
  void for_each_pair(std::size_t first, std::size_t last, Visit&& visit) const {
    for (std::size_t bucket = first; bucket < last; ++bucket) {
      const std::uint32_t end = bucket_start_[bucket + 1];
      for (std::uint32_t k = bucket_start_[bucket]; k < end; ++k) {
        const Entry& a = entries_[k];
        for (std::uint32_t m = k + 1; m < end; ++m) {
          const Entry& b = entries_[m];
          if (a.cell[0] != b.cell[0] || a.cell[1] != b.cell[1] || a.cell[2] != b.cell[2]) continue;
          // The intersection's lowest corner in this cell (as in for_each_overlap).
          if ((a.lowest | b.lowest) != kEveryAxis || !overlap(boxes_[a.box], boxes_[b.box])) continue;
          visit(a.box, b.box);  // a.box < b.box: a bucket's entries are in box order
        }
      }
    }
    if (first != 0) return;
    for (std::size_t k = 0; k < oversize_.size(); ++k) {
      const std::uint32_t big = oversize_[k];
      for (std::uint32_t j = 0; j < boxes_.size(); ++j) {
        // Two kept-aside boxes are paired once, when the smaller index is `big`.
        const bool paired_already = j < big && std::binary_search(oversize_.begin(), oversize_.end(), j);
        if (j == big || paired_already) continue;
        if (overlap(boxes_[big], boxes_[j])) visit(std::min(big, j), std::max(big, j));
      }
    }
  }
  std::size_t bucket_count() const { return bucket_start_.empty() ? 0 : bucket_start_.size() - 1; }

  double cell_size() const { return cell_size_; }
  std::size_t bytes() const;

  // The grid as built, which the device's grid (gpu/device_box_grid.h) reproduces: each bucket's
  // entries are entries()[bucket_starts()[b] .. bucket_starts()[b + 1]), by box and then cell; the
  // boxes kept aside, ascending; the cells the entered boxes span.
  using Cell = std::array<std::int64_t, 3>;
  struct Entry {
    Cell cell;
    std::uint32_t box;
    std::uint8_t lowest;  // bit a set where `cell` is the box's lowest cell along axis a
  };
  std::span<const std::uint32_t> bucket_starts() const { return bucket_start_; }
  std::span<const Entry> entries() const { return entries_; }
  std::span<const std::uint32_t> oversize() const { return oversize_; }
  std::array<Cell, 2> extent() const { return {extent_low_, extent_high_}; }
  // A box more than this many cells across on some axis is kept aside.
  static constexpr double kOversize = 8.0;

 private:
  static constexpr unsigned kEveryAxis = 7;
  Cell cell_of(const Vec3& x) const;
  std::size_t bucket_of(const Cell& cell) const;
  // Calls f(cell) for every cell from `low` to `high` (a box's lowest and highest corners' cells).
  template <typename F>
  static void for_each_cell(const Cell& low, const Cell& high, F&& f) {
    for (std::int64_t x = low[0]; x <= high[0]; ++x) {
      for (std::int64_t y = low[1]; y <= high[1]; ++y) {
        for (std::int64_t z = low[2]; z <= high[2]; ++z) f(Cell{x, y, z});
      }
    }
  }

  std::span<const Box> boxes_;
  double cell_size_ = 1.0;                   // m
  std::size_t bucket_mask_ = 0;              // buckets - 1 (a power of two)
  std::vector<std::uint32_t> bucket_start_;  // [buckets + 1] CSR into entries_
  std::vector<Entry> entries_;               // by bucket, then box index
  std::vector<Cell> low_cell_;               // [boxes] the cell of each box's lowest corner
  std::vector<std::uint32_t> oversize_;      // boxes kept aside (see the top of the file), ascending
  Cell extent_low_{};                        // the cells the entered boxes span
  Cell extent_high_{};
  static constexpr std::size_t kBuildBlock = 4096;  // boxes, or buckets, per block of build()
  std::vector<std::uint32_t> fill_;                 // scratch of build(): next free entry per bucket
  std::vector<std::uint32_t> cells_of_;             // scratch of build(): cells each box enters, 0 kept aside
};

// Every pair (i, j) with queries[i] overlapping stored[j], by visiting all pairs: the oracle the
// grid is tested against. In (i, j) lexicographic order.
std::vector<std::array<std::uint32_t, 2>> overlapping_pairs_brute_force(std::span<const Box> queries,
                                                                        std::span<const Box> stored);

}  // namespace clothsim
