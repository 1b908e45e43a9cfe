#include "integrators/multigrid.h"

#include <algorithm>

#include "core/assert.h"
#include "core/multiversion.h"
#include "core/parallel.h"
#include "core/shared_text.h"

namespace clothsim {
namespace {

// The stencil's slots and the prolongation's parents, shared with the device's V-cycle
// (gpu/device_multigrid.h).
namespace stencil {
#include "integrators/multigrid_stencil.inc"
}  // namespace stencil

constexpr auto kSlots = static_cast<std::size_t>(stencil::kStencilSlots);

// A coarse row's blocks: the offsets (di, dj) in [-2, 2]^2 but the corners, in ascending node order.
const std::array<SymmetricStencilMatrix::Offset, kSlots> kOffsets = [] {
  std::array<SymmetricStencilMatrix::Offset, kSlots> offsets{};
  for (int slot = 0; slot < stencil::kStencilSlots; ++slot) {
    offsets[static_cast<std::size_t>(slot)] = {stencil::stencil_row_offset(slot), stencil::stencil_column_offset(slot)};
  }
  return offsets;
}();
// The coarse rows' upper half: the slots from here on.
constexpr auto kDiagonalSlot = static_cast<std::size_t>(stencil::kStencilDiagonal);

// The fine lattice's upper stencil: the elements join particles one row or column apart
// (connectors, adjacent radial springs: (1, -1), (1, 1)) or two along a row or column (opposite
// radial springs).
constexpr std::array<SymmetricStencilMatrix::Offset, 7> kFineUpper = {
    {{0, 0}, {0, 1}, {0, 2}, {1, -1}, {1, 0}, {1, 1}, {2, 0}}};

// The fine stencil's slot of upper offset (di, dj).
constexpr std::size_t fine_upper_slot(int di, int dj) {
  std::size_t slot = 0;
  while (kFineUpper[slot] != SymmetricStencilMatrix::Offset{di, dj}) ++slot;
  return slot;
}
// Per line direction (0: along a row, 1: along a column), the fine stencil's slots of a node's
// blocks to itself and to the nodes 1 and 2 after it on its line.
constexpr std::array<std::array<std::size_t, 3>, 2> kLineSlots = {
    {{fine_upper_slot(0, 0), fine_upper_slot(0, 1), fine_upper_slot(0, 2)},
     {fine_upper_slot(0, 0), fine_upper_slot(1, 0), fine_upper_slot(2, 0)}}};

// The slot of offset (di, dj), both in [-2, 2], not a corner.
std::size_t stencil_slot(int di, int dj) { return static_cast<std::size_t>(stencil::stencil_slot(di, dj)); }

// How many nodes ahead a line solve down a column asks the cache for the matrix rows and vectors
// it will read (SymmetricStencilMatrix::prefetch).
constexpr std::size_t kColumnAhead = 4;

// Rows per band of the Gauss-Seidel sweeps (at least 2: bands two apart must share no matrix entry).
constexpr std::size_t kBandRows = 4;

// Levels with fewer nodes run on one thread: a parallel loop's start costs more than it saves.
constexpr std::size_t kParallelNodes = 1024;

int level_threads(std::size_t nodes, int threads) { return nodes >= kParallelNodes ? threads : 1; }

// Calls body(first, end) for the bands of kBandRows of `count` rows (or lines): the even bands in
// parallel, then the odd ones (the reverse when descending).
template <typename Body>
void for_each_band(std::size_t count, bool ascending, int threads, Body&& body) {
  const std::size_t bands = (count + kBandRows - 1) / kBandRows;
  for (std::size_t step = 0; step < 2; ++step) {
    const std::size_t parity = ascending ? step : 1 - step;
    parallel_for((bands + 1 - parity) / 2, threads, [&](std::size_t k) {
      const std::size_t band = parity + 2 * k;
      body(band * kBandRows, std::min(count, (band + 1) * kBandRows));
    });
  }
}

}  // namespace

LatticeMultigrid::LatticeMultigrid(std::size_t rows, std::size_t cols, bool lines)
    : rows_(rows), cols_(cols), fine_stencil_(rows, cols, kFineUpper), lines_(lines) {
  static_assert(kStencil == kSlots, "multigrid_stencil.inc's slots");
  CLOTHSIM_ASSERT(rows > 0 && cols > 0, "a lattice");
  fine_residual_.assign(rows * cols, Vec3{});
  if (lines_) {
    for (LineFactor& factor : line_factor_) {
      for (std::vector<Mat3>* blocks : {&factor.below, &factor.two_below, &factor.diagonal_inverse}) {
        blocks->assign(rows * cols, Mat3{});
      }
    }
    line_vector_.assign(rows * cols, Vec3{});
  }
  std::size_t level_rows = rows;
  std::size_t level_cols = cols;
  do {
    level_rows = (level_rows + 1) / 2;
    level_cols = (level_cols + 1) / 2;
    CoarseLevel level;
    level.along_rows = make_transfer(coarse_.empty() ? rows : coarse_.back().rows, level_rows);
    level.along_cols = make_transfer(coarse_.empty() ? cols : coarse_.back().cols, level_cols);
    level.rows = level_rows;
    level.cols = level_cols;
    for (std::size_t s = 0; s < kStencil; ++s) {
      level.node_offset[s] = kOffsets[s][0] * static_cast<std::ptrdiff_t>(level_cols) + kOffsets[s][1];
    }
    const std::size_t nodes = level_rows * level_cols;
    level.block.assign(nodes * kStencil, Mat3{});
    level.diagonal_inverse.assign(nodes, Mat3{});
    level.stencil = SymmetricStencilMatrix(level_rows, level_cols, std::span(kOffsets).subspan(kDiagonalSlot));
    for (std::vector<Vec3>* vector : {&level.rhs, &level.solution, &level.residual}) vector->assign(nodes, Vec3{});
    coarse_.push_back(std::move(level));
  } while (level_rows * level_cols > kCoarsestNodes);
  // Nodes couple up to 2 rows and 1 column apart, or 1 row and 2 columns: 2 cols + 1 nodes.
  coarsest_.resize(3 * level_rows * level_cols, 3 * (2 * level_cols + 1) + 2);
  coarsest_vector_.assign(coarsest_.dofs(), 0.0);
}

LatticeMultigrid::Transfer LatticeMultigrid::make_transfer(std::size_t fine_count, std::size_t coarse_count) {
  Transfer transfer;
  transfer.parents.resize(fine_count);
  transfer.children.resize(coarse_count);
  for (std::size_t fine = 0; fine < fine_count; ++fine) {
    const auto count = stencil::parent_count(static_cast<int>(fine), static_cast<int>(coarse_count));
    const double weight = 0.5 * stencil::twice_parent_weight(static_cast<int>(fine), static_cast<int>(coarse_count));
    Weights& parents = transfer.parents[fine];
    for (int k = 0; k < count; ++k) {
      const std::size_t coarse = fine / 2 + static_cast<std::size_t>(k);
      parents.node[parents.count] = coarse;
      parents.weight[parents.count++] = weight;
      Weights& children = transfer.children[coarse];  // ascending: the fine nodes come in order
      children.node[children.count] = fine;
      children.weight[children.count++] = weight;
    }
  }
  return transfer;
}

std::size_t LatticeMultigrid::bytes() const {
  std::size_t total = fine_residual_.capacity() * sizeof(Vec3) + fine_stencil_.bytes() + coarsest_.bytes();
  total += coarsest_vector_.capacity() * sizeof(double) + line_vector_.capacity() * sizeof(Vec3);
  for (const LineFactor& factor : line_factor_) {
    total +=
        (factor.below.capacity() + factor.two_below.capacity() + factor.diagonal_inverse.capacity()) * sizeof(Mat3);
  }
  for (const CoarseLevel& level : coarse_) {
    total += (level.block.capacity() + level.diagonal_inverse.capacity()) * sizeof(Mat3) + level.stencil.bytes();
    total += (level.rhs.capacity() + level.solution.capacity() + level.residual.capacity()) * sizeof(Vec3);
    for (const Transfer* transfer : {&level.along_rows, &level.along_cols}) {
      total += (transfer->parents.capacity() + transfer->children.capacity()) * sizeof(Weights);
    }
  }
  return total;
}

std::size_t LatticeMultigrid::bytes_for(std::size_t rows, std::size_t cols, bool lines) {
  std::size_t total = rows * cols * sizeof(Vec3) + SymmetricStencilMatrix::bytes_for(rows * cols, kFineUpper.size());
  if (lines) total += rows * cols * (2 * 3 * sizeof(Mat3) + sizeof(Vec3));  // 2 factors of 3 blocks, the vector
  std::size_t level_rows = rows;
  std::size_t level_cols = cols;
  do {
    total += (level_rows + level_cols) * sizeof(Weights);  // the transfer's parents
    level_rows = (level_rows + 1) / 2;
    level_cols = (level_cols + 1) / 2;
    total += (level_rows + level_cols) * sizeof(Weights);  // and children
    const std::size_t nodes = level_rows * level_cols;
    total += nodes * ((kStencil + 1) * sizeof(Mat3) + 3 * sizeof(Vec3)) +
             SymmetricStencilMatrix::bytes_for(nodes, kStencil - kDiagonalSlot);
  } while (level_rows * level_cols > kCoarsestNodes);
  const std::size_t dofs = 3 * level_rows * level_cols;
  return total + BandedCholesky::bytes_for(dofs, 3 * (2 * level_cols + 1) + 2) + dofs * sizeof(double);
}

[[gnu::always_inline]] inline Vec3 LatticeMultigrid::row_product(std::size_t level, std::size_t node,
                                                                 std::span<const Vec3> x) const {
  if (level > 0) return coarse_[level - 1].stencil.row_product(node, x);
  const Vec3 sum = fine_stencil_.row_product(node, x);
  return fine_.holding ? held_vector(fine_.hold[node], fine_.normal[node], sum) : sum;
}

[[gnu::always_inline]] inline void LatticeMultigrid::update_node(std::size_t level, std::size_t node,
                                                                 std::span<const Vec3> rhs, std::span<Vec3> x) const {
  if (level == 0) {
    if (!fine_.free[node]) return;
    const Vec3 change = fine_.diagonal_inverse[node] * (rhs[node] - row_product(0, node, x));
    x[node] += fine_.holding ? held_vector(fine_.hold[node], fine_.normal[node], change) : change;
  } else {
    x[node] += coarse_[level - 1].diagonal_inverse[node] * (rhs[node] - row_product(level, node, x));
  }
}

// Compiled for each instruction set (core/multiversion.h): the sweeps are most of the V-cycle.
// What it calls is always_inline, so that each version holds the whole sweep (a lambda here was
// compiled once, for the baseline, and called from every version).
CLOTHSIM_MULTIVERSION void LatticeMultigrid::smooth_nodes(std::size_t level, std::size_t first, std::size_t end,
                                                          bool ascending, std::span<const Vec3> rhs,
                                                          std::span<Vec3> x) const {
  if (ascending) {
    for (std::size_t node = first; node < end; ++node) update_node(level, node, rhs, x);
  } else {
    for (std::size_t node = end; node-- > first;) update_node(level, node, rhs, x);
  }
}

CLOTHSIM_MULTIVERSION void LatticeMultigrid::residual_nodes(std::size_t level, std::size_t first, std::size_t end,
                                                            std::span<const Vec3> rhs, std::span<const Vec3> x,
                                                            std::span<Vec3> residual) const {
  for (std::size_t node = first; node < end; ++node) {
    residual[node] = level == 0 && !fine_.free[node] ? Vec3{} : rhs[node] - row_product(level, node, x);
  }
}

void LatticeMultigrid::smooth(std::size_t level, bool ascending, std::span<const Vec3> rhs, std::span<Vec3> x,
                              int threads) {
  const std::size_t rows = level == 0 ? rows_ : coarse_[level - 1].rows;
  const std::size_t cols = level == 0 ? cols_ : coarse_[level - 1].cols;
  for_each_band(rows, ascending, level_threads(rows * cols, threads), [&](std::size_t first, std::size_t end) {
    smooth_nodes(level, first * cols, end * cols, ascending, rhs, x);
  });
}

std::array<Mat3, 3> LatticeMultigrid::line_blocks(std::size_t node, int direction) const {
  std::array<Mat3, 3> blocks{};
  if (!fine_.free[node]) return blocks;
  // The blocks as the smoother's residuals read them: the stencil's, and a block to a node before
  // this one the transpose of that node's block to this one. Then the line solve's matrix is the
  // residual's, and the cycle symmetric.
  const std::size_t position = direction == 0 ? node % cols_ : node / cols_;  // on the line
  const std::size_t step = direction == 0 ? 1 : cols_;
  const std::array<std::size_t, 3>& slot = kLineSlots[static_cast<std::size_t>(direction)];
  for (std::size_t before = 0; before <= std::min<std::size_t>(2, position); ++before) {
    const std::size_t q = node - before * step;
    Mat3 block = before == 0 ? fine_stencil_.block(node, slot[0]) : transpose(fine_stencil_.block(q, slot[before]));
    if (fine_.holding && (fine_.hold[node] != Hold::none || fine_.hold[q] != Hold::none)) {
      const double mean = (block(0, 0) + block(1, 1) + block(2, 2)) / 3.0;
      block = held_block(block, fine_.hold[node], fine_.normal[node], fine_.hold[q], fine_.normal[q]);
      if (before == 0 && fine_.hold[node] == Hold::normal)
        block += mean * outer(fine_.normal[node], fine_.normal[node]);
    }
    blocks[before] = block;
  }
  return blocks;
}

void LatticeMultigrid::factor_lines(int direction, int threads) {
  const std::size_t count = direction == 0 ? rows_ : cols_;
  const std::size_t length = direction == 0 ? cols_ : rows_;
  LineFactor& factor = line_factor_[static_cast<std::size_t>(direction)];
  parallel_for(count, level_threads(rows_ * cols_, threads), [&](std::size_t line) {
    // A = L D L^T, block by block along the line: with A's blocks a0 (to itself), a1, a2 (to the
    // nodes 1 and 2 before) and w = a1 - a2 L1(t-1)^T = L1(t) D(t-1):
    //   L2(t) = a2 D(t-2)^-1,  L1(t) = w D(t-1)^-1,  D(t) = a0 - w L1(t)^T - a2 L2(t)^T.
    Mat3* below = &factor.below[line * length];
    Mat3* two_below = &factor.two_below[line * length];
    Mat3* diagonal_inverse = &factor.diagonal_inverse[line * length];
    for (std::size_t t = 0; t < length; ++t) {
      // Down a column, the row of the stencil kColumnAhead nodes on (as solve_line).
      if (direction == 1 && t + kColumnAhead < length) fine_stencil_.prefetch((t + kColumnAhead) * cols_ + line, 1);
      const std::array<Mat3, 3> a = line_blocks(direction == 0 ? line * cols_ + t : t * cols_ + line, direction);
      const Mat3 w = t >= 2 ? a[1] - times_transpose(a[2], below[t - 1]) : a[1];
      // D's inverses are symmetric, so a D^-1 = a (D^-1)^T.
      two_below[t] = t >= 2 ? times_transpose(a[2], diagonal_inverse[t - 2]) : Mat3{};
      below[t] = t >= 1 ? times_transpose(w, diagonal_inverse[t - 1]) : Mat3{};
      Mat3 d = a[0];
      if (t >= 1) d -= times_transpose(w, below[t]);
      if (t >= 2) d -= times_transpose(a[2], two_below[t]);
      // A node outside the system (anchored, or held in every direction) has no equation: a zero
      // inverse, and so a zero solution. D is symmetrised against rounding.
      const double trace = d(0, 0) + d(1, 1) + d(2, 2);
      diagonal_inverse[t] = trace > 0.0 ? inverse(0.5 * (d + transpose(d))) : Mat3{};
    }
  });
}

// x = A_line^-1 (rhs - A_off x) on one line, A_off the blocks to the other lines: L, D and L^T
// solved in turn.
[[gnu::always_inline]] inline void LatticeMultigrid::solve_line(int direction, std::size_t line,
                                                                std::span<const Vec3> rhs, std::span<Vec3> x) {
  const std::size_t length = direction == 0 ? cols_ : rows_;
  const LineFactor& factor = line_factor_[static_cast<std::size_t>(direction)];
  const std::size_t first_node = direction == 0 ? line * cols_ : line;  // the line's node t at first + t step
  const std::size_t step = direction == 0 ? 1 : cols_;
  const Mat3* below = &factor.below[line * length];
  const Mat3* two_below = &factor.two_below[line * length];
  const Mat3* diagonal_inverse = &factor.diagonal_inverse[line * length];
  Vec3* v = &line_vector_[line * length];
  for (std::size_t t = 0; t < length; ++t) {
    const std::size_t node = first_node + t * step;
    if (direction == 1 && t + kColumnAhead < length) {
      // Down a column the nodes are a lattice row apart: the rows this node's off-line product
      // reads, (i, j - 2 .. j) and (i - 1, j +- 1), kColumnAhead nodes on.
      const std::size_t ahead = node + kColumnAhead * step;
      fine_stencil_.prefetch(ahead - std::min<std::size_t>(line, 2), 4);
      __builtin_prefetch(&x[ahead - std::min<std::size_t>(line, 2)]);
      __builtin_prefetch(&x[ahead + 2 < rows_ * cols_ ? ahead + 2 : ahead]);
      __builtin_prefetch(&rhs[ahead]);
    }
    Vec3 y;
    if (fine_.free[node]) {
      const Vec3 off_line = fine_stencil_.row_product_off_line(node, x, direction);
      y = rhs[node] - (fine_.holding ? held_vector(fine_.hold[node], fine_.normal[node], off_line) : off_line);
    }
    if (t >= 1) y -= below[t] * v[t - 1];
    if (t >= 2) y -= two_below[t] * v[t - 2];
    v[t] = y;
  }
  for (std::size_t t = length; t-- > 0;) {
    Vec3 z = diagonal_inverse[t] * v[t];
    if (t + 1 < length) z -= transpose_times(below[t + 1], v[t + 1]);
    if (t + 2 < length) z -= transpose_times(two_below[t + 2], v[t + 2]);
    v[t] = z;
  }
  for (std::size_t t = 0; t < length; ++t) {
    const std::size_t node = first_node + t * step;
    if (fine_.free[node]) x[node] = fine_.holding ? held_vector(fine_.hold[node], fine_.normal[node], v[t]) : v[t];
  }
}

// Compiled for each instruction set (core/multiversion.h), as smooth_nodes.
CLOTHSIM_MULTIVERSION void LatticeMultigrid::solve_lines(int direction, std::size_t first, std::size_t end,
                                                         bool ascending, std::span<const Vec3> rhs,
                                                         std::span<Vec3> x) {
  if (ascending) {
    for (std::size_t line = first; line < end; ++line) solve_line(direction, line, rhs, x);
  } else {
    for (std::size_t line = end; line-- > first;) solve_line(direction, line, rhs, x);
  }
}

void LatticeMultigrid::smooth_lines(int direction, bool ascending, std::span<const Vec3> rhs, std::span<Vec3> x,
                                    int threads) {
  const std::size_t count = direction == 0 ? rows_ : cols_;
  for_each_band(count, ascending, level_threads(rows_ * cols_, threads), [&](std::size_t first, std::size_t end) {
    solve_lines(direction, first, end, ascending, rhs, x);
  });
}

void LatticeMultigrid::smooth_fine(bool ascending, std::span<const Vec3> rhs, std::span<Vec3> x, int threads) {
  for (int sweep = 0; sweep < (lines_ ? kFineLineSweeps : kFineSweeps); ++sweep) {
    if (!lines_) {
      smooth(0, ascending, rhs, x, threads);
      continue;
    }
    // Along the rows, then the columns; descending, the reverse.
    for (int k = 0; k < 2; ++k) smooth_lines(ascending ? k : 1 - k, ascending, rhs, x, threads);
  }
}

void LatticeMultigrid::restrict_residual(std::size_t level, std::span<const Vec3> rhs, std::span<const Vec3> x,
                                         int threads) {
  const std::size_t rows = level == 0 ? rows_ : coarse_[level - 1].rows;
  const std::size_t cols = level == 0 ? cols_ : coarse_[level - 1].cols;
  std::vector<Vec3>& residual = level == 0 ? fine_residual_ : coarse_[level - 1].residual;
  parallel_for(rows, level_threads(rows * cols, threads),
               [&](std::size_t row) { residual_nodes(level, row * cols, (row + 1) * cols, rhs, x, residual); });
  CoarseLevel& next = coarse_[level];
  parallel_for(next.rows * next.cols, level_threads(rows * cols, threads), [&](std::size_t node) {
    const Weights& row_children = next.along_rows.children[node / next.cols];
    const Weights& col_children = next.along_cols.children[node % next.cols];
    Vec3 sum;
    for (std::size_t a = 0; a < row_children.count; ++a) {
      for (std::size_t b = 0; b < col_children.count; ++b) {
        sum += (row_children.weight[a] * col_children.weight[b]) *
               residual[row_children.node[a] * cols + col_children.node[b]];
      }
    }
    next.rhs[node] = sum;
  });
}

void LatticeMultigrid::prolong(std::size_t level, std::span<Vec3> x, int threads) {
  const std::size_t rows = level == 0 ? rows_ : coarse_[level - 1].rows;
  const std::size_t cols = level == 0 ? cols_ : coarse_[level - 1].cols;
  const CoarseLevel& next = coarse_[level];
  parallel_for(rows * cols, level_threads(rows * cols, threads), [&](std::size_t node) {
    if (level == 0 && !fine_.free[node]) return;
    const Weights& row_parents = next.along_rows.parents[node / cols];
    const Weights& col_parents = next.along_cols.parents[node % cols];
    Vec3 sum;
    for (std::size_t a = 0; a < row_parents.count; ++a) {
      for (std::size_t b = 0; b < col_parents.count; ++b) {
        sum += (row_parents.weight[a] * col_parents.weight[b]) *
               next.solution[row_parents.node[a] * next.cols + col_parents.node[b]];
      }
    }
    x[node] += level == 0 && fine_.holding ? held_vector(fine_.hold[node], fine_.normal[node], sum) : sum;
  });
}

void LatticeMultigrid::galerkin(std::size_t level, int threads) {
  const std::size_t nodes = level == 0 ? rows_ * cols_ : coarse_[level - 1].rows * coarse_[level - 1].cols;
  const CoarseLevel& next = coarse_[level];
  parallel_for(next.rows * next.cols, level_threads(nodes, threads),
               [&](std::size_t node) { galerkin_row(level, node); });
}

[[gnu::always_inline]] inline void LatticeMultigrid::add_to_parents(const CoarseLevel& next, std::size_t row,
                                                                    std::size_t col, std::size_t i, std::size_t j,
                                                                    double weight, const Mat3& block,
                                                                    Mat3* sum) const {
  const Weights& row_parents = next.along_rows.parents[i];
  const Weights& col_parents = next.along_cols.parents[j];
  for (std::size_t a = 0; a < row_parents.count; ++a) {
    for (std::size_t b = 0; b < col_parents.count; ++b) {
      const auto di = static_cast<int>(static_cast<std::ptrdiff_t>(row_parents.node[a] - row));
      const auto dj = static_cast<int>(static_cast<std::ptrdiff_t>(col_parents.node[b] - col));
      sum[stencil_slot(di, dj)] += (weight * row_parents.weight[a] * col_parents.weight[b]) * block;
    }
  }
}

// Row I of P^T A P: the sum over I's children p and the blocks (p, q) of w(p, I) w(q, J) A_pq, J
// over q's parents, in a fixed order. Compiled for each instruction set (core/multiversion.h):
// the products are most of the preconditioner's setup.
CLOTHSIM_MULTIVERSION void LatticeMultigrid::galerkin_row(std::size_t level, std::size_t node) {
  const std::size_t rows = level == 0 ? rows_ : coarse_[level - 1].rows;
  const std::size_t cols = level == 0 ? cols_ : coarse_[level - 1].cols;
  CoarseLevel& next = coarse_[level];
  const std::size_t row = node / next.cols;
  const std::size_t col = node % next.cols;
  std::array<Mat3, kStencil> sum{};
  const Weights& row_children = next.along_rows.children[row];
  const Weights& col_children = next.along_cols.children[col];
  for (std::size_t a = 0; a < row_children.count; ++a) {
    for (std::size_t b = 0; b < col_children.count; ++b) {
      const std::size_t i = row_children.node[a];
      const std::size_t j = col_children.node[b];
      const double weight = row_children.weight[a] * col_children.weight[b];
      const std::size_t p = i * cols + j;
      if (level > 0) {
        const Mat3* block = &coarse_[level - 1].block[p * kStencil];
        for (std::size_t s = 0; s < kStencil; ++s) {
          const std::ptrdiff_t qi = static_cast<std::ptrdiff_t>(i) + kOffsets[s][0];
          const std::ptrdiff_t qj = static_cast<std::ptrdiff_t>(j) + kOffsets[s][1];
          if (qi < 0 || qj < 0 || qi >= static_cast<std::ptrdiff_t>(rows) || qj >= static_cast<std::ptrdiff_t>(cols))
            continue;
          add_to_parents(next, row, col, static_cast<std::size_t>(qi), static_cast<std::size_t>(qj), weight, block[s],
                         sum.data());
        }
        continue;
      }
      // The fine level: its free rows and columns, in the solved directions.
      if (!fine_.free[p] || (fine_.holding && fine_.hold[p] == Hold::all)) continue;
      for (std::uint32_t k = fine_.row_offset[p]; k < fine_.row_offset[p + 1]; ++k) {
        const std::uint32_t q = fine_.column[k];
        if (!fine_.free[q]) continue;
        const bool filtered = fine_.holding && (fine_.hold[p] != Hold::none || fine_.hold[q] != Hold::none);
        add_to_parents(next, row, col, q / cols, q % cols, weight,
                       filtered ? held_block(fine_.block[k], fine_.hold[p], fine_.normal[p], fine_.hold[q],
                                             fine_.normal[q])
                                : fine_.block[k],
                       sum.data());
      }
    }
  }
  std::copy(sum.begin(), sum.end(), &next.block[node * kStencil]);
  // The smoother's block: the diagonal's inverse, zero for a node no free particle reaches.
  // The tiny shift keeps it finite where the held directions of all its children coincide
  // (the diagonal is then singular in a direction in which its right-hand side is zero).
  for (std::size_t slot = kDiagonalSlot; slot < kStencil; ++slot) {
    next.stencil.set(node, slot - kDiagonalSlot, sum[slot]);
  }
  const Mat3& diagonal = sum[kDiagonalSlot];
  const double trace = diagonal(0, 0) + diagonal(1, 1) + diagonal(2, 2);
  next.diagonal_inverse[node] = trace > 0.0 ? inverse(diagonal + Mat3::diagonal(1e-12 * trace)) : Mat3{};
}

void LatticeMultigrid::setup(const MultigridFineSystem& fine, int threads) {
  CLOTHSIM_ASSERT(fine.row_offset.size() == rows_ * cols_ + 1, "the fine system is the lattice's");
  fine_ = fine;
  // The fine matrix's free rows and columns, upper half, for the smoother and the residuals.
  parallel_for(rows_ * cols_, level_threads(rows_ * cols_, threads), [&](std::size_t p) {
    fine_stencil_.clear_row(p);
    if (!fine_.free[p]) return;
    const auto row = static_cast<int>(p / cols_);
    const auto col = static_cast<int>(p % cols_);
    for (std::uint32_t k = fine_.row_offset[p]; k < fine_.row_offset[p + 1]; ++k) {
      const std::uint32_t q = fine_.column[k];
      const int di = static_cast<int>(q / cols_) - row;
      const int dj = static_cast<int>(q % cols_) - col;
      const bool upper = di > 0 || (di == 0 && dj >= 0);
      const std::size_t slot = upper ? fine_stencil_.slot(di, dj) : fine_stencil_.slot(-di, -dj);
      CLOTHSIM_ASSERT(slot < SymmetricStencilMatrix::kMaxSlots, "the fine matrix couples lattice neighbours only");
      if (upper && fine_.free[q]) fine_stencil_.set(p, slot, fine_.block[k]);
    }
  });
  for (std::size_t level = 0; level < coarse_.size(); ++level) galerkin(level, threads);
  if (lines_) {
    for (int direction = 0; direction < 2; ++direction) factor_lines(direction, threads);
  }
  // The coarsest matrix's lower triangle into the banded factor.
  const CoarseLevel& last = coarse_.back();
  coarsest_.clear();
  for (std::size_t node = 0; node < last.rows * last.cols; ++node) {
    const auto row = static_cast<std::ptrdiff_t>(node / last.cols);
    const auto col = static_cast<std::ptrdiff_t>(node % last.cols);
    for (std::size_t s = 0; s <= kDiagonalSlot; ++s) {  // the offsets before the node, and itself
      const std::ptrdiff_t i = row + kOffsets[s][0];
      const std::ptrdiff_t j = col + kOffsets[s][1];
      if (i < 0 || j < 0 || j >= static_cast<std::ptrdiff_t>(last.cols)) continue;
      const std::size_t other = static_cast<std::size_t>(i) * last.cols + static_cast<std::size_t>(j);
      const Mat3& block = last.block[node * kStencil + s];
      for (std::size_t r = 0; r < 3; ++r) {
        for (std::size_t c = 0; c < 3; ++c) {
          if (3 * other + c <= 3 * node + r) {
            coarsest_.lower(3 * node + r, 3 * other + c) = block(static_cast<int>(r), static_cast<int>(c));
          }
        }
      }
    }
  }
  coarsest_.factor();
}

void LatticeMultigrid::apply(std::span<const Vec3> residual, std::span<Vec3> result, int threads) {
  std::fill(result.begin(), result.end(), Vec3{});
  const std::size_t last = coarse_.size();  // the coarsest level's index
  // Down: smooth from zero, restrict the residual.
  smooth_fine(true, residual, result, threads);
  restrict_residual(0, residual, result, threads);
  for (std::size_t level = 1; level < last; ++level) {
    CoarseLevel& coarse = coarse_[level - 1];
    std::fill(coarse.solution.begin(), coarse.solution.end(), Vec3{});
    for (int sweep = 0; sweep < kCoarseSweeps; ++sweep) smooth(level, true, coarse.rhs, coarse.solution, threads);
    restrict_residual(level, coarse.rhs, coarse.solution, threads);
  }
  // The coarsest level exactly.
  CoarseLevel& coarsest = coarse_.back();
  for (std::size_t node = 0; node < coarsest.rhs.size(); ++node) {
    for (int k = 0; k < 3; ++k) coarsest_vector_[3 * node + static_cast<std::size_t>(k)] = coarsest.rhs[node][k];
  }
  coarsest_.solve(coarsest_vector_);
  for (std::size_t node = 0; node < coarsest.solution.size(); ++node) {
    coarsest.solution[node] = {coarsest_vector_[3 * node], coarsest_vector_[3 * node + 1],
                               coarsest_vector_[3 * node + 2]};
  }
  // Up: add the correction, smooth in the reverse order.
  for (std::size_t level = last - 1; level >= 1; --level) {
    CoarseLevel& coarse = coarse_[level - 1];
    prolong(level, coarse.solution, threads);
    for (int sweep = 0; sweep < kCoarseSweeps; ++sweep) smooth(level, false, coarse.rhs, coarse.solution, threads);
  }
  prolong(0, result, threads);
  smooth_fine(false, residual, result, threads);
}

}  // namespace clothsim
