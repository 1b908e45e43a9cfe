#include "collision/box_grid.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace clothsim {

std::array<std::int64_t, 3> BoxGrid::cell_of(const Vec3& x) const {
  // Positions are finite (the simulation's checks stop a run before they are not); the clamp
  // keeps a huge one from overflowing the conversion.
  const auto coordinate = [this](double value) {
    return static_cast<std::int64_t>(std::clamp(std::floor(value / cell_size_), -1e15, 1e15));
  };
  return {coordinate(x.x), coordinate(x.y), coordinate(x.z)};
}

std::size_t BoxGrid::bucket_of(const std::array<std::int64_t, 3>& cell) const {
  // Teschner et al., "Optimized spatial hashing for collision detection of deformable objects"
  // (VMV 2003): three large primes, combined by exclusive or.
  const auto hash = (static_cast<std::uint64_t>(cell[0]) * 73856093u) ^ (static_cast<std::uint64_t>(cell[1]) * 19349663u) ^
                    (static_cast<std::uint64_t>(cell[2]) * 83492791u);
  return static_cast<std::size_t>(hash) & bucket_mask_;
}

void BoxGrid::build(std::span<const Box> boxes) {
  boxes_ = boxes;
  double extent = 0.0;
  for (const Box& box : boxes) {
    extent = std::max({extent, box.high.x - box.low.x, box.high.y - box.low.y, box.high.z - box.low.z});
  }
  // A positive cell even for point-sized boxes.
  cell_size_ = extent > 0.0 ? extent : 1.0;
  const std::size_t buckets = std::bit_ceil(std::max<std::size_t>(2 * boxes.size(), 16));
  bucket_mask_ = buckets - 1;
  bucket_start_.assign(buckets + 1, 0);
  entries_.resize(boxes.size());
  // Counting sort by bucket, stable in box index.
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    entries_[i].cell = cell_of(boxes[i].low);
    ++bucket_start_[bucket_of(entries_[i].cell) + 1];
  }
  for (std::size_t b = 0; b < buckets; ++b) bucket_start_[b + 1] += bucket_start_[b];
  fill_.assign(bucket_start_.begin(), bucket_start_.end() - 1);
  sorted_.resize(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const std::size_t bucket = bucket_of(entries_[i].cell);
    sorted_[fill_[bucket]++] = {entries_[i].cell, static_cast<std::uint32_t>(i)};
  }
  entries_.swap(sorted_);
}

std::size_t BoxGrid::bytes() const {
  return (bucket_start_.capacity() + fill_.capacity()) * sizeof(std::uint32_t) +
         (entries_.capacity() + sorted_.capacity()) * sizeof(Entry);
}

std::vector<std::array<std::uint32_t, 2>> overlapping_pairs_brute_force(std::span<const Box> queries,
                                                                       std::span<const Box> stored) {
  std::vector<std::array<std::uint32_t, 2>> pairs;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    for (std::size_t j = 0; j < stored.size(); ++j) {
      if (overlap(queries[i], stored[j])) pairs.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)});
    }
  }
  return pairs;
}

}  // namespace clothsim
