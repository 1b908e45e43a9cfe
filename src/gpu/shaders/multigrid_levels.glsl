// The V-cycle's level arrays as its shaders read them (multigrid_step.h gives the layout): a node's
// matrix blocks, where its stencil's neighbours are, the colours of the sweeps and the transfer's
// weights. The includer declares the float array level_blocks ([nodes of all levels][kStencilSlots]
// [9], each block column by column: single precision in either precision of the shaders, as the
// CPU stores its levels, integrators/stencil_matrix.h; the products are formed in Real) and includes the shared text's spelling first
// (shared_text.glsl). With CLOTHSIM_COARSE_LEVELS defined it also declares the coarse levels'
// vectors (level_rhs, level_solution, level_residual, [3 nodes] each) and smoother blocks
// (level_diagonal_inverse, [nodes][9]), and gets the operations on a coarse level below.
#ifndef CLOTHSIM_MULTIGRID_LEVELS_GLSL
#define CLOTHSIM_MULTIGRID_LEVELS_GLSL
#include "integrators/multigrid_stencil.inc"

// A level: its first node in the level arrays and its nodes in each direction.
struct Level {
  uint base;
  uint rows;
  uint cols;
};

uint node_count(Level level) { return level.rows * level.cols; }

// The next coarser level (LatticeMultigrid's: every other node, rounding up).
Level coarser(Level level) { return Level(level.base + node_count(level), (level.rows + 1u) / 2u, (level.cols + 1u) / 2u); }

uint block_index(uint node, int slot) { return 9u * (uint(kStencilSlots) * node + uint(slot)); }

Mat3 level_block(uint node, int slot) {
  const uint i = block_index(node, slot);
  return Mat3(level_blocks[i], level_blocks[i + 1], level_blocks[i + 2], level_blocks[i + 3], level_blocks[i + 4],
              level_blocks[i + 5], level_blocks[i + 6], level_blocks[i + 7], level_blocks[i + 8]);
}

// The node at `slot`'s offset from node (i, j) of a rows x cols level; false where that is off the level.
bool stencil_neighbour(uint i, uint j, int slot, uint rows, uint cols, out uint neighbour) {
  const int row = int(i) + stencil_row_offset(slot);
  const int col = int(j) + stencil_column_offset(slot);
  neighbour = uint(row) * cols + uint(col);
  return row >= 0 && col >= 0 && row < int(rows) && col < int(cols);
}

// The sweeps' colours (multigrid_step.h): the nodes of `colour` on a level, and the k-th of them.
uint colour_nodes(Level level, uint colour) {
  return ((level.rows + 2u - colour / 3u) / 3u) * ((level.cols + 2u - colour % 3u) / 3u);
}
uint colour_node(Level level, uint colour, uint k) {
  const uint colour_cols = (level.cols + 2u - colour % 3u) / 3u;
  return (colour / 3u + 3u * (k / colour_cols)) * level.cols + colour % 3u + 3u * (k % colour_cols);
}

// The fine nodes along one direction that coarse node `coarse` interpolates to: first and last
// (2 coarse - 1 .. 2 coarse + 1, within the fine level's `fine_count`).
uint first_child(uint coarse) { return coarse > 0u ? 2u * coarse - 1u : 0u; }
uint last_child(uint coarse, uint fine_count) { return min(fine_count - 1u, 2u * coarse + 1u); }

// The weight of coarse node `coarse` in fine node `fine`'s interpolation along one direction, zero
// where it is not one of its parents.
Real parent_weight(uint fine, uint coarse, uint coarse_count) {
  const int first = int(fine) / 2;
  const int count = parent_count(int(fine), int(coarse_count));
  const bool parent = int(coarse) == first || (count == 2 && int(coarse) == first + 1);
  return parent ? Real(0.5) * Real(twice_parent_weight(int(fine), int(coarse_count))) : Real(0.0);
}

#ifdef CLOTHSIM_COARSE_LEVELS

const uint kLevelRhs = 0u, kLevelSolution = 1u, kLevelResidual = 2u;

Vec3 level_vector3(uint array, uint node) {
  const uint i = 3u * node;
  if (array == kLevelRhs) return Vec3(level_rhs[i], level_rhs[i + 1u], level_rhs[i + 2u]);
  if (array == kLevelSolution) return Vec3(level_solution[i], level_solution[i + 1u], level_solution[i + 2u]);
  return Vec3(level_residual[i], level_residual[i + 1u], level_residual[i + 2u]);
}

void set_level_solution(uint node, Vec3 x) {
  for (uint k = 0u; k < 3u; ++k) level_solution[3u * node + k] = x[k];
}

// rhs - A x at node `node` of a coarse level.
Vec3 coarse_residual(Level level, uint node) {
  const uint i = node / level.cols;
  const uint j = node % level.cols;
  Vec3 product = Vec3(0.0);
  for (int s = 0; s < kStencilSlots; ++s) {
    uint q;
    if (stencil_neighbour(i, j, s, level.rows, level.cols, q)) {
      product += level_block(level.base + node, s) * level_vector3(kLevelSolution, level.base + q);
    }
  }
  return level_vector3(kLevelRhs, level.base + node) - product;
}

// Gauss-Seidel's update of one node of a coarse level: x += D^-1 (rhs - A x).
void coarse_smooth(Level level, uint node) {
  const uint i = 9u * (level.base + node);
  const Mat3 smoother =
      Mat3(level_diagonal_inverse[i], level_diagonal_inverse[i + 1], level_diagonal_inverse[i + 2],
           level_diagonal_inverse[i + 3], level_diagonal_inverse[i + 4], level_diagonal_inverse[i + 5],
           level_diagonal_inverse[i + 6], level_diagonal_inverse[i + 7], level_diagonal_inverse[i + 8]);
  const Vec3 x = level_vector3(kLevelSolution, level.base + node);
  set_level_solution(level.base + node, x + smoother * coarse_residual(level, node));
}

// The residual of node `node` of a coarse level into level_residual.
void store_coarse_residual(Level level, uint node) {
  const Vec3 r = coarse_residual(level, node);
  for (uint k = 0u; k < 3u; ++k) level_residual[3u * (level.base + node) + k] = r[k];
}

// Node `node` of the next level: its rhs = P^T (level's residual), its solution 0. Any level
// (level 0's residual is in level_residual too).
void restrict_to(Level level, Level next, uint node) {
  const uint row = node / next.cols;
  const uint col = node % next.cols;
  Vec3 sum = Vec3(0.0);
  for (uint i = first_child(row); i <= last_child(row, level.rows); ++i) {
    const Real row_weight = parent_weight(i, row, next.rows);
    if (row_weight == Real(0.0)) continue;
    for (uint j = first_child(col); j <= last_child(col, level.cols); ++j) {
      const Real col_weight = parent_weight(j, col, next.cols);
      if (col_weight == Real(0.0)) continue;
      sum += (row_weight * col_weight) * level_vector3(kLevelResidual, level.base + i * level.cols + j);
    }
  }
  for (uint k = 0u; k < 3u; ++k) {
    level_rhs[3u * (next.base + node) + k] = sum[k];
    level_solution[3u * (next.base + node) + k] = Real(0.0);
  }
}

// P (the next level's solution) at node `node` of a level.
Vec3 interpolated(Level level, Level next, uint node) {
  const uint row = node / level.cols;
  const uint col = node % level.cols;
  Vec3 sum = Vec3(0.0);
  for (int a = 0; a < parent_count(int(row), int(next.rows)); ++a) {
    const uint parent_row = row / 2u + uint(a);
    const Real weight_a = parent_weight(row, parent_row, next.rows);
    for (int b = 0; b < parent_count(int(col), int(next.cols)); ++b) {
      const uint parent_col = col / 2u + uint(b);
      const Real weight_b = parent_weight(col, parent_col, next.cols);
      sum += (weight_a * weight_b) * level_vector3(kLevelSolution, next.base + parent_row * next.cols + parent_col);
    }
  }
  return sum;
}

#endif
#endif
