// A symmetric matrix of 3x3 blocks on a rows x cols lattice whose nodes couple to nodes at most
// two rows and two columns away, stored for the multigrid V-cycle's smoother and residuals
// (integrators/multigrid.h), which read every level's matrix five times per CG iteration.
//
// Storage. Node (i, j) is index i cols + j. Only the upper half of the stencil is kept: for each
// node its block to itself (slot 0) and to the neighbours after it in node order, offsets
// (di, dj) with di > 0, or di = 0 and dj > 0; the block to a neighbour before it is the transpose
// of that neighbour's block to it, so the stored operator is symmetric whatever the rounding. The
// blocks are single precision, the products sum in double. The V-cycle is a preconditioner: its
// operator need only be close to the system's, and symmetric positive definite, which the matrix
// keeps as long as its rounding (6e-8 relative) is far below its smallest eigenvalue relative to
// its largest (cloth's systems are mass-dominated on the diagonal).
//
// Why. On 128 x 128 cotton the V-cycle's passes over the matrices were 61 % of implicit Euler's
// step, bound by memory: a fine row was 13 blocks of 72 bytes and 13 column indices, 988 bytes;
// here it is 7 blocks of 36 bytes, 252 bytes, and a coarse row 11 of 36 instead of 21 of 72
// (docs/performance.md, "A cheaper implicit Euler step").
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "core/mat3.h"

namespace clothsim {

class SymmetricStencilMatrix {
 public:
  using Offset = std::array<int, 2>;            // (di, dj): rows, then columns
  static constexpr std::size_t kMaxSlots = 11;  // the upper half of [-2, 2]^2 without its corners

  SymmetricStencilMatrix() = default;
  // A zero matrix whose rows keep the blocks at `upper` ((0, 0) first, then offsets after the
  // node in node order, each within [-2, 2] in both directions).
  SymmetricStencilMatrix(std::size_t rows, std::size_t cols, std::span<const Offset> upper);

  // The slot of upper offset (di, dj), or kMaxSlots when the stencil does not hold it.
  std::size_t slot(int di, int dj) const;
  std::size_t slot_count() const { return slots_; }
  // Row `node`'s block at `slot`, rounded to single precision.
  void set(std::size_t node, std::size_t slot, const Mat3& block) { block_[node * slots_ + slot] = narrow(block); }
  // Row `node`'s block at `slot`, as stored (rounded to single precision).
  Mat3 block(std::size_t node, std::size_t slot) const { return widen(block_[node * slots_ + slot]); }
  // Every block of row `node` to zero.
  void clear_row(std::size_t node);
  // Row `node` times x ([rows cols]).
  [[gnu::always_inline]] Vec3 row_product(std::size_t node, std::span<const Vec3> x) const {
    return product(node, x, [](std::size_t) { return true; });
  }
  // Row `node` times x without the blocks to the nodes on the node's own lattice row (`line` 0:
  // offsets (0, dj), itself included) or column (1: offsets (di, 0)): what a line solve of the
  // multigrid's smoother takes from the other lines.
  [[gnu::always_inline]] Vec3 row_product_off_line(std::size_t node, std::span<const Vec3> x, int line) const {
    const std::size_t across = line == 0 ? 0 : 1;  // the offset's component that is 0 on the line
    return product(node, x, [&](std::size_t s) { return offset_[s][across] != 0; });
  }

  // Asks the cache for rows [first, first + count) (clamped to the matrix) ahead of their use: a
  // sweep down a lattice column reads rows a lattice row apart, a stride the hardware's
  // prefetchers do not follow.
  [[gnu::always_inline]] void prefetch(std::size_t first, std::size_t count) const {
    constexpr std::size_t kCacheLine = 64;
    const std::size_t end = std::min(rows_ * cols_, first + count);
    if (first >= end) return;
    const auto* begin = reinterpret_cast<const char*>(&block_[first * slots_]);
    const std::size_t bytes = (end - first) * slots_ * sizeof(Block);
    for (std::size_t byte = 0; byte < bytes; byte += kCacheLine) __builtin_prefetch(begin + byte);
  }

  std::size_t bytes() const { return block_.capacity() * sizeof(Block); }
  static std::size_t bytes_for(std::size_t nodes, std::size_t slots) { return nodes * slots * sizeof(Block); }

 private:
  using Block = FloatBlock;

  // Row `node` times x over the slots s with keep(s) (the block to itself is slot 0).
  template <typename Keep>
  [[gnu::always_inline]] Vec3 product(std::size_t node, std::span<const Vec3> x, Keep keep) const;

  std::size_t rows_ = 0;
  std::size_t cols_ = 0;
  std::size_t slots_ = 0;
  std::array<Offset, kMaxSlots> offset_{};
  // di cols + dj: positive, an upper neighbour comes after the node (0 where the lattice is too
  // narrow for the offset, which then never lies inside it).
  std::array<std::size_t, kMaxSlots> node_offset_{};
  std::vector<Block> block_;  // [rows cols slots], row `node` from node slots
};

template <typename Keep>
[[gnu::always_inline]] inline Vec3 SymmetricStencilMatrix::product(std::size_t node, std::span<const Vec3> x,
                                                                   Keep keep) const {
  const Block* own = &block_[node * slots_];
  Vec3 upper = keep(0) ? times(own[0], x[node]) : Vec3{};
  Vec3 lower;
  const std::size_t row = node / cols_;
  const std::size_t col = node % cols_;
  if (row >= 2 && col >= 2 && row + 2 < rows_ && col + 2 < cols_) {
    // An interior node: every neighbour exists.
    for (std::size_t s = 1; s < slots_; ++s) {
      if (!keep(s)) continue;
      const std::size_t d = node_offset_[s];
      upper += times(own[s], x[node + d]);
      lower += transpose_times(block_[(node - d) * slots_ + s], x[node - d]);
    }
    return upper + lower;
  }
  const auto inside = [&](std::ptrdiff_t i, std::ptrdiff_t j) {
    return i >= 0 && j >= 0 && i < static_cast<std::ptrdiff_t>(rows_) && j < static_cast<std::ptrdiff_t>(cols_);
  };
  const auto r = static_cast<std::ptrdiff_t>(row);
  const auto c = static_cast<std::ptrdiff_t>(col);
  for (std::size_t s = 1; s < slots_; ++s) {
    if (!keep(s)) continue;
    const std::size_t d = node_offset_[s];
    if (inside(r + offset_[s][0], c + offset_[s][1])) upper += times(own[s], x[node + d]);
    if (inside(r - offset_[s][0], c - offset_[s][1]))
      lower += transpose_times(block_[(node - d) * slots_ + s], x[node - d]);
  }
  return upper + lower;
}

}  // namespace clothsim
