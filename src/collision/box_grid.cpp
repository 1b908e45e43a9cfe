#include "collision/box_grid.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace clothsim {

BoxGrid::Cell BoxGrid::cell_of(const Vec3& x) const {
  // Positions are finite (the simulation's checks stop a run before they are not); the clamp
  // keeps a huge one from overflowing the conversion.
  const auto coordinate = [this](double value) {
    return static_cast<std::int64_t>(std::clamp(std::floor(value / cell_size_), -1e15, 1e15));
  };
  return {coordinate(x.x), coordinate(x.y), coordinate(x.z)};
}

std::size_t BoxGrid::bucket_of(const Cell& cell) const {
  // Teschner et al., "Optimized spatial hashing for collision detection of deformable objects"
  // (VMV 2003): three large primes, combined by exclusive or.
  const auto hash = (static_cast<std::uint64_t>(cell[0]) * 73856093u) ^
                    (static_cast<std::uint64_t>(cell[1]) * 19349663u) ^
                    (static_cast<std::uint64_t>(cell[2]) * 83492791u);
  return static_cast<std::size_t>(hash) & bucket_mask_;
}

namespace {
double extent_of(const Box& box) {
  return std::max({box.high.x - box.low.x, box.high.y - box.low.y, box.high.z - box.low.z});
}
}  // namespace

void BoxGrid::build(std::span<const Box> boxes) {
  boxes_ = boxes;
  double sum = 0.0;
  for (const Box& box : boxes) sum += extent_of(box);
  const double mean = boxes.empty() ? 0.0 : sum / static_cast<double>(boxes.size());
  // A positive cell even for point-sized boxes.
  cell_size_ = mean > 0.0 ? mean : 1.0;

  oversize_.clear();
  low_cell_.resize(boxes.size());
  constexpr std::int64_t kFar = std::numeric_limits<std::int64_t>::max();
  extent_low_ = {kFar, kFar, kFar};
  extent_high_ = {-kFar, -kFar, -kFar};
  std::size_t entries = 0;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    low_cell_[i] = cell_of(boxes[i].low);
    if (extent_of(boxes[i]) > kOversize * cell_size_) {
      oversize_.push_back(static_cast<std::uint32_t>(i));
      continue;
    }
    const Cell high = cell_of(boxes[i].high);
    for (int axis = 0; axis < 3; ++axis) {
      extent_low_[axis] = std::min(extent_low_[axis], low_cell_[i][axis]);
      extent_high_[axis] = std::max(extent_high_[axis], high[axis]);
    }
    for_each_cell(low_cell_[i], high, [&entries](const Cell&) { ++entries; });
  }
  const std::size_t buckets = std::bit_ceil(std::max<std::size_t>(2 * entries, 16));
  bucket_mask_ = buckets - 1;
  bucket_start_.assign(buckets + 1, 0);
  const auto entered = [this](std::size_t i) {
    return oversize_.empty() || !std::binary_search(oversize_.begin(), oversize_.end(), static_cast<std::uint32_t>(i));
  };
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    if (!entered(i)) continue;
    for_each_cell(low_cell_[i], cell_of(boxes[i].high), [this](const Cell& c) { ++bucket_start_[bucket_of(c) + 1]; });
  }
  for (std::size_t b = 0; b < buckets; ++b) bucket_start_[b + 1] += bucket_start_[b];
  // Counting sort by bucket, stable in box index.
  fill_.assign(bucket_start_.begin(), bucket_start_.end() - 1);
  entries_.resize(entries);
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    if (!entered(i)) continue;
    for_each_cell(low_cell_[i], cell_of(boxes[i].high), [&](const Cell& c) {
      const Cell& low = low_cell_[i];
      const auto lowest = static_cast<std::uint8_t>((c[0] == low[0] ? 1 : 0) | (c[1] == low[1] ? 2 : 0) |
                                                    (c[2] == low[2] ? 4 : 0));
      entries_[fill_[bucket_of(c)]++] = {c, static_cast<std::uint32_t>(i), lowest};
    });
  }
}

std::size_t BoxGrid::bytes() const {
  return (bucket_start_.capacity() + fill_.capacity()) * sizeof(std::uint32_t) + entries_.capacity() * sizeof(Entry) +
         low_cell_.capacity() * sizeof(Cell) + oversize_.capacity() * sizeof(std::uint32_t);
}

std::vector<std::array<std::uint32_t, 2>> overlapping_pairs_brute_force(std::span<const Box> queries,
                                                                        std::span<const Box> stored) {
  std::vector<std::array<std::uint32_t, 2>> pairs;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    for (std::size_t j = 0; j < stored.size(); ++j) {
      if (overlap(queries[i], stored[j]))
        pairs.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)});
    }
  }
  return pairs;
}

}  // namespace clothsim
