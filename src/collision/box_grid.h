// The broad phase of self-collision: which axis-aligned boxes overlap, in time linear in their
// number (collision/self_contacts.h).
//
// A uniform grid, hashed. Each stored box is entered once, in the cell holding its lowest corner;
// the cell size is the largest extent of any stored box, so a stored box that overlaps a query
// box has its lowest corner at most one cell below the query's lowest corner on every axis. A
// query therefore visits the cells from one below its lowest corner's to its highest corner's
// (3 x 3 x 3 for a query no larger than a cell) and finds every overlapping stored box exactly
// once: an entry is taken only from the cell it was entered in, even where two cells share a
// hash bucket. Cells are hashed into a table of about twice as many buckets as boxes, so the
// memory is linear in the boxes wherever they are, and the entries of a bucket are kept in box
// index order (a counting sort), so every query reports in the same order for any thread count.
//
// Rejected: a sort-and-sweep along one axis (a sheet lying flat puts all of it in one slab of
// that axis), and a bounding-volume hierarchy (rebuilt or refitted every step, with a worse
// constant for boxes of near-equal size, which a lattice's triangles are).
#pragma once

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
  // Enters `boxes` (kept by reference: they must outlive the queries and stay unchanged).
  void build(std::span<const Box> boxes);

  // Calls visit(j) for every stored box j that overlaps `query`, each once, in bucket order.
  template <typename Visit>
  void for_each_overlap(const Box& query, Visit&& visit) const {
    if (boxes_.empty()) return;
    const std::array<std::int64_t, 3> low = cell_of(query.low);
    const std::array<std::int64_t, 3> high = cell_of(query.high);
    for (std::int64_t x = low[0] - 1; x <= high[0]; ++x) {
      for (std::int64_t y = low[1] - 1; y <= high[1]; ++y) {
        for (std::int64_t z = low[2] - 1; z <= high[2]; ++z) {
          const std::array<std::int64_t, 3> cell = {x, y, z};
          const std::size_t bucket = bucket_of(cell);
          for (std::uint32_t k = bucket_start_[bucket]; k < bucket_start_[bucket + 1]; ++k) {
            const Entry& entry = entries_[k];
            if (entry.cell != cell || !overlap(boxes_[entry.box], query)) continue;
            visit(entry.box);
          }
        }
      }
    }
  }

  double cell_size() const { return cell_size_; }
  std::size_t bytes() const;

 private:
  struct Entry {
    std::array<std::int64_t, 3> cell;
    std::uint32_t box;
  };
  std::array<std::int64_t, 3> cell_of(const Vec3& x) const;
  std::size_t bucket_of(const std::array<std::int64_t, 3>& cell) const;

  std::span<const Box> boxes_;
  double cell_size_ = 1.0;                   // m
  std::size_t bucket_mask_ = 0;              // buckets - 1 (a power of two)
  std::vector<std::uint32_t> bucket_start_;  // [buckets + 1] CSR into entries_
  std::vector<Entry> entries_;               // [boxes] by bucket, then box index
  std::vector<std::uint32_t> fill_;          // scratch of build(): next free entry per bucket
  std::vector<Entry> sorted_;                // scratch of build()
};

// Every pair (i, j) with queries[i] overlapping stored[j], by visiting all pairs: the oracle the
// grid is tested against. In (i, j) lexicographic order.
std::vector<std::array<std::uint32_t, 2>> overlapping_pairs_brute_force(std::span<const Box> queries,
                                                                       std::span<const Box> stored);

}  // namespace clothsim
