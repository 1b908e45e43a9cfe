#version 450
#extension GL_GOOGLE_include_directive : require
// The V-cycle's coarse matrices (gpu/device_multigrid.h): level l + 1's from level l's, Galerkin's
// A_{l+1} = P^T A_l P with P the bilinear prolongation (integrators/multigrid_stencil.inc), one
// invocation per coarse node, as LatticeMultigrid::galerkin computes a row on the CPU: over the
// node's children in ascending order, each child's blocks in ascending node order, each block to
// its column's parents. Also the smoother's block of the node: the inverse of its diagonal, shifted
// by 1e-12 of its trace (finite where the held directions of all its children coincide), or zero
// where no free particle reaches it.
#include "gpu/shaders/shared_text.glsl"
#include "gpu/shaders/multigrid_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) buffer LevelBlocks { float level_blocks[]; };
layout(std430, binding = 1) writeonly buffer LevelDiagonalInverse { Real level_diagonal_inverse[]; };  // [nodes][9]

layout(push_constant) uniform Constants { MultigridPassConstants constants; };

#include "gpu/shaders/multigrid_levels.glsl"

void main() {
  const uint node = invocation_index();
  if (node >= constants.next_rows * constants.next_cols) return;
  const uint row = node / constants.next_cols;
  const uint col = node % constants.next_cols;
  Mat3 sum[kStencilSlots];
  for (int s = 0; s < kStencilSlots; ++s) sum[s] = Mat3(0.0);
  for (uint i = first_child(row); i <= last_child(row, constants.rows); ++i) {
    const Real row_weight = parent_weight(i, row, constants.next_rows);
    if (row_weight == Real(0.0)) continue;
    for (uint j = first_child(col); j <= last_child(col, constants.cols); ++j) {
      const Real col_weight = parent_weight(j, col, constants.next_cols);
      if (col_weight == Real(0.0)) continue;
      const Real child_weight = row_weight * col_weight;
      const uint child = i * constants.cols + j;
      for (int s = 0; s < kStencilSlots; ++s) {
        uint q;
        if (!stencil_neighbour(i, j, s, constants.rows, constants.cols, q)) continue;
        const Mat3 block = level_block(constants.base + child, s);
        const uint q_row = q / constants.cols;
        const uint q_col = q % constants.cols;
        // q's parents: first at q / 2, a second at q / 2 + 1 where it has two.
        for (int a = 0; a < parent_count(int(q_row), int(constants.next_rows)); ++a) {
          const uint parent_row = q_row / 2u + uint(a);
          const Real weight_a = parent_weight(q_row, parent_row, constants.next_rows);
          for (int b = 0; b < parent_count(int(q_col), int(constants.next_cols)); ++b) {
            const uint parent_col = q_col / 2u + uint(b);
            const Real weight_b = parent_weight(q_col, parent_col, constants.next_cols);
            const int slot = stencil_slot(int(parent_row) - int(row), int(parent_col) - int(col));
            sum[slot] += (child_weight * weight_a * weight_b) * block;
          }
        }
      }
    }
  }
  const uint coarse = constants.next_base + node;
  for (int s = 0; s < kStencilSlots; ++s) {
    const uint i = block_index(coarse, s);
    for (uint column = 0u; column < 3u; ++column) {
      for (uint r = 0u; r < 3u; ++r) level_blocks[i + 3u * column + r] = float(sum[s][column][r]);
    }
  }
  const Mat3 diagonal = sum[kStencilDiagonal];
  const Real trace = diagonal[0][0] + diagonal[1][1] + diagonal[2][2];
  const Mat3 smoother = trace > Real(0.0) ? inverse(diagonal + (Real(1e-12) * trace) * Mat3(1.0)) : Mat3(0.0);
  for (uint column = 0u; column < 3u; ++column) {
    for (uint r = 0u; r < 3u; ++r) level_diagonal_inverse[9u * coarse + 3u * column + r] = smoother[column][r];
  }
}
