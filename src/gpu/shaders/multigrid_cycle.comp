#version 450
#extension GL_GOOGLE_include_directive : require
// The V-cycle's passes on one level (gpu/device_multigrid.h; LatticeMultigrid::apply on the CPU):
//   kCycleClear     level 0's solution (the preconditioned residual z) = 0, where the cycle starts
//   kCycleSmooth    one colour of a Gauss-Seidel sweep, one invocation per node of the colour:
//                   x += D^-1 (rhs - A x) (level 0: the held directions filtered out, anchored
//                   particles left out). Colours ascending down the V and descending up it, so the
//                   cycle is symmetric, as conjugate gradients require
//   kCycleResidual  the level's residual rhs - A x (zero where anchored)
//   kCycleRestrict  one invocation per node of the next level: its rhs = P^T residual, its solution 0
//   kCycleProlong   x += P (the next level's solution) (level 0: filtered, anchored particles left out)
// Level 0's rhs and solution are the conjugate gradients' residual r and preconditioned residual z.
// The passes of a CG iteration return at once once the solve has stopped.
#include "gpu/shaders/shared_text.glsl"
#include "gpu/shaders/implicit_step.h"
#include "gpu/shaders/multigrid_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer LevelBlocks { Real level_blocks[]; };
layout(std430, binding = 1) readonly buffer LevelDiagonalInverse { Real level_diagonal_inverse[]; };  // [nodes][9]
layout(std430, binding = 2) readonly buffer Jacobi { Real jacobi[]; };  // [particles][9]: level 0's smoother
layout(std430, binding = 3) buffer LevelRhs { Real level_rhs[]; };            // [3 nodes]
layout(std430, binding = 4) buffer LevelSolution { Real level_solution[]; };  // [3 nodes]
layout(std430, binding = 5) buffer LevelResidual { Real level_residual[]; };  // [3 nodes]
layout(std430, binding = 6) readonly buffer Residual { Real residual[]; };    // [3 particles], CG's r
layout(std430, binding = 7) buffer Preconditioned { Real preconditioned[]; }; // [3 particles], CG's z
layout(std430, binding = 8) readonly buffer ParticleAnchor { int particle_anchor[]; };
layout(std430, binding = 9) readonly buffer Hold { uint hold[]; };
layout(std430, binding = 10) readonly buffer SurfaceContacts { Real surface_contacts[]; };
layout(std430, binding = 11) readonly buffer SolveUint { uint solve_uint[]; };

layout(push_constant) uniform Constants { MultigridPassConstants constants; };

#include "gpu/shaders/held_directions.glsl"
#include "gpu/shaders/multigrid_levels.glsl"

bool fine() { return constants.level == 0u; }

Vec3 rhs_at(uint node) {
  if (fine()) return Vec3(residual[3u * node], residual[3u * node + 1u], residual[3u * node + 2u]);
  const uint i = 3u * (constants.base + node);
  return Vec3(level_rhs[i], level_rhs[i + 1u], level_rhs[i + 2u]);
}

Vec3 solution_at(uint node) {
  if (fine()) return Vec3(preconditioned[3u * node], preconditioned[3u * node + 1u], preconditioned[3u * node + 2u]);
  const uint i = 3u * (constants.base + node);
  return Vec3(level_solution[i], level_solution[i + 1u], level_solution[i + 2u]);
}

void set_solution(uint node, Vec3 x) {
  for (uint k = 0u; k < 3u; ++k) {
    if (fine()) {
      preconditioned[3u * node + k] = x[k];
    } else {
      level_solution[3u * (constants.base + node) + k] = x[k];
    }
  }
}

Mat3 smoother_block(uint node) {
  const uint i = 9u * (fine() ? node : constants.base + node);
  if (fine()) {
    return Mat3(jacobi[i], jacobi[i + 1], jacobi[i + 2], jacobi[i + 3], jacobi[i + 4], jacobi[i + 5], jacobi[i + 6],
                jacobi[i + 7], jacobi[i + 8]);
  }
  return Mat3(level_diagonal_inverse[i], level_diagonal_inverse[i + 1], level_diagonal_inverse[i + 2],
              level_diagonal_inverse[i + 3], level_diagonal_inverse[i + 4], level_diagonal_inverse[i + 5],
              level_diagonal_inverse[i + 6], level_diagonal_inverse[i + 7], level_diagonal_inverse[i + 8]);
}

// Level 0's rows of anchored particles are outside the system.
bool outside(uint node) { return fine() && particle_anchor[node] >= 0; }

// rhs - A x at a node of the level (its matrix already filtered on level 0, multigrid_assemble).
Vec3 node_residual(uint node) {
  const uint i = node / constants.cols;
  const uint j = node % constants.cols;
  Vec3 product = Vec3(0.0);
  for (int s = 0; s < kStencilSlots; ++s) {
    uint q;
    if (stencil_neighbour(i, j, s, constants.rows, constants.cols, q)) {
      product += level_block(constants.base + node, s) * solution_at(q);
    }
  }
  return rhs_at(node) - product;
}

void smooth_colour() {
  const uint colour_row = constants.colour / 3u;
  const uint colour_col = constants.colour % 3u;
  const uint colour_cols = (constants.cols + 2u - colour_col) / 3u;
  const uint colour_rows = (constants.rows + 2u - colour_row) / 3u;
  const uint k = invocation_index();
  if (k >= colour_rows * colour_cols) return;
  const uint node = (colour_row + 3u * (k / colour_cols)) * constants.cols + colour_col + 3u * (k % colour_cols);
  if (outside(node)) return;
  const Vec3 change = smoother_block(node) * node_residual(node);
  set_solution(node, solution_at(node) + (fine() ? held(node, change) : change));
}

void restrict_residual() {
  const uint node = invocation_index();
  if (node >= constants.next_rows * constants.next_cols) return;
  const uint row = node / constants.next_cols;
  const uint col = node % constants.next_cols;
  Vec3 sum = Vec3(0.0);
  for (uint i = first_child(row); i <= last_child(row, constants.rows); ++i) {
    const Real row_weight = parent_weight(i, row, constants.next_rows);
    if (row_weight == Real(0.0)) continue;
    for (uint j = first_child(col); j <= last_child(col, constants.cols); ++j) {
      const Real col_weight = parent_weight(j, col, constants.next_cols);
      if (col_weight == Real(0.0)) continue;
      const uint child = 3u * (constants.base + i * constants.cols + j);
      sum += (row_weight * col_weight) * Vec3(level_residual[child], level_residual[child + 1u], level_residual[child + 2u]);
    }
  }
  const uint coarse = 3u * (constants.next_base + node);
  for (uint k = 0u; k < 3u; ++k) {
    level_rhs[coarse + k] = sum[k];
    level_solution[coarse + k] = Real(0.0);
  }
}

void prolong() {
  const uint node = invocation_index();
  if (node >= constants.rows * constants.cols || outside(node)) return;
  const uint row = node / constants.cols;
  const uint col = node % constants.cols;
  Vec3 sum = Vec3(0.0);
  for (int a = 0; a < parent_count(int(row), int(constants.next_rows)); ++a) {
    const uint parent_row = row / 2u + uint(a);
    const Real weight_a = parent_weight(row, parent_row, constants.next_rows);
    for (int b = 0; b < parent_count(int(col), int(constants.next_cols)); ++b) {
      const uint parent_col = col / 2u + uint(b);
      const Real weight_b = parent_weight(col, parent_col, constants.next_cols);
      const uint i = 3u * (constants.next_base + parent_row * constants.next_cols + parent_col);
      sum += (weight_a * weight_b) * Vec3(level_solution[i], level_solution[i + 1u], level_solution[i + 2u]);
    }
  }
  set_solution(node, solution_at(node) + (fine() ? held(node, sum) : sum));
}

void main() {
  if (constants.iteration != 0u && solve_uint[kSolveDone] != 0u) return;
  if (constants.phase == kCycleSmooth) {
    smooth_colour();
  } else if (constants.phase == kCycleRestrict) {
    restrict_residual();
  } else if (constants.phase == kCycleProlong) {
    prolong();
  } else {
    const uint node = invocation_index();
    if (node >= constants.rows * constants.cols) return;
    if (constants.phase == kCycleClear) {
      set_solution(node, Vec3(0.0));
      return;
    }
    const Vec3 r = outside(node) ? Vec3(0.0) : node_residual(node);
    const uint i = 3u * (constants.base + node);
    for (uint k = 0u; k < 3u; ++k) level_residual[i + k] = r[k];
  }
}
