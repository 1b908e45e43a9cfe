#include "collision/box_grid.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>

#include "core/parallel.h"

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

void BoxGrid::build(std::span<const Box> boxes, int threads) {
  boxes_ = boxes;
  // In box order, one thread: the cell size's rounding, and so the cells, do not depend on the
  // threads.
  double sum = 0.0;
  for (const Box& box : boxes) sum += extent_of(box);
  const double mean = boxes.empty() ? 0.0 : sum / static_cast<double>(boxes.size());
  // A positive cell even for point-sized boxes.
  cell_size_ = mean > 0.0 ? mean : 1.0;

  // Each box's lowest cell and the cells it spans (0: kept aside); which are kept aside, in
  // order; the cells the entered boxes span, by blocks of boxes (a minimum and a maximum are the
  // same in any order).
  const std::size_t count = boxes.size();
  low_cell_.resize(count);
  cells_of_.resize(count);
  const std::size_t blocks = (count + kBuildBlock - 1) / kBuildBlock;
  constexpr std::int64_t kFar = std::numeric_limits<std::int64_t>::max();
  std::vector<std::array<Cell, 2>> block_extent(blocks, {Cell{kFar, kFar, kFar}, Cell{-kFar, -kFar, -kFar}});
  std::vector<std::size_t> block_entries(blocks, 0);
  parallel_for(blocks, threads, [&](std::size_t block) {
    auto& [low, high] = block_extent[block];
    for (std::size_t i = block * kBuildBlock; i < std::min(count, (block + 1) * kBuildBlock); ++i) {
      low_cell_[i] = cell_of(boxes[i].low);
      if (extent_of(boxes[i]) > kOversize * cell_size_) {
        cells_of_[i] = 0;
        continue;
      }
      const Cell box_high = cell_of(boxes[i].high);
      std::uint32_t cells = 1;
      for (int axis = 0; axis < 3; ++axis) {
        low[axis] = std::min(low[axis], low_cell_[i][axis]);
        high[axis] = std::max(high[axis], box_high[axis]);
        cells *= static_cast<std::uint32_t>(box_high[axis] - low_cell_[i][axis] + 1);
      }
      cells_of_[i] = cells;
      block_entries[block] += cells;
    }
  });
  parallel_select(count, threads, [this](std::size_t i) { return cells_of_[i] == 0; }, oversize_);
  extent_low_ = {kFar, kFar, kFar};
  extent_high_ = {-kFar, -kFar, -kFar};
  std::size_t entries = 0;
  for (std::size_t block = 0; block < blocks; ++block) {
    for (int axis = 0; axis < 3; ++axis) {
      extent_low_[axis] = std::min(extent_low_[axis], block_extent[block][0][axis]);
      extent_high_[axis] = std::max(extent_high_[axis], block_extent[block][1][axis]);
    }
    entries += block_entries[block];
  }

  // Counting sort of the entries by bucket. Serial, it enters them in box order, each box's cells
  // in for_each_cell's order; in parallel, each thread takes the next free place in a bucket, and
  // each bucket is then sorted into that order: the same entries in the same places.
  const std::size_t buckets = std::bit_ceil(std::max<std::size_t>(2 * entries, 16));
  bucket_mask_ = buckets - 1;
  bucket_start_.assign(buckets + 1, 0);
  const auto for_each_entered_cell = [&](auto&& f) {
    parallel_for(blocks, threads, [&](std::size_t block) {
      for (std::size_t i = block * kBuildBlock; i < std::min(count, (block + 1) * kBuildBlock); ++i) {
        if (cells_of_[i] != 0) for_each_cell(low_cell_[i], cell_of(boxes[i].high), [&](const Cell& c) { f(i, c); });
      }
    });
  };
  const bool serial = threads <= 1 || blocks <= 1;
  for_each_entered_cell([&](std::size_t, const Cell& c) {
    std::uint32_t& tally = bucket_start_[bucket_of(c) + 1];
    if (serial) {
      ++tally;
    } else {
      std::atomic_ref<std::uint32_t>(tally).fetch_add(1, std::memory_order_relaxed);
    }
  });
  for (std::size_t b = 0; b < buckets; ++b) bucket_start_[b + 1] += bucket_start_[b];
  fill_.assign(bucket_start_.begin(), bucket_start_.end() - 1);
  entries_.resize(entries);
  for_each_entered_cell([&](std::size_t i, const Cell& c) {
    const Cell& low = low_cell_[i];
    const auto lowest =
        static_cast<std::uint8_t>((c[0] == low[0] ? 1 : 0) | (c[1] == low[1] ? 2 : 0) | (c[2] == low[2] ? 4 : 0));
    std::uint32_t& next = fill_[bucket_of(c)];
    const std::uint32_t place =
        serial ? next++ : std::atomic_ref<std::uint32_t>(next).fetch_add(1, std::memory_order_relaxed);
    entries_[place] = {c, static_cast<std::uint32_t>(i), lowest};
  });
  if (serial) return;
  parallel_for((buckets + kBuildBlock - 1) / kBuildBlock, threads, [&](std::size_t block) {
    for (std::size_t b = block * kBuildBlock; b < std::min(buckets, (block + 1) * kBuildBlock); ++b) {
      const auto first = entries_.begin() + bucket_start_[b];
      const auto last = entries_.begin() + bucket_start_[b + 1];
      if (last - first < 2) continue;
      std::sort(first, last, [](const Entry& x, const Entry& y) {
        return x.box != y.box ? x.box < y.box : x.cell < y.cell;  // a box's cells: x, then y, then z
      });
    }
  });
}

std::size_t BoxGrid::bytes() const {
  return (bucket_start_.capacity() + fill_.capacity() + cells_of_.capacity()) * sizeof(std::uint32_t) +
         entries_.capacity() * sizeof(Entry) + low_cell_.capacity() * sizeof(Cell) +
         oversize_.capacity() * sizeof(std::uint32_t);
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
