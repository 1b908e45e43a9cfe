// The V-cycle's level arrays as its shaders read them (multigrid_step.h gives the layout): a node's
// matrix blocks and where its stencil's neighbours are. The includer declares the Real array
// level_blocks ([nodes of all levels][kStencilSlots][9], each block column by column) and includes
// the shared text's spelling first (shared_text.glsl).
#ifndef CLOTHSIM_MULTIGRID_LEVELS_GLSL
#define CLOTHSIM_MULTIGRID_LEVELS_GLSL
#include "integrators/multigrid_stencil.inc"

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

#endif
