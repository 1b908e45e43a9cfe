#version 450
#extension GL_GOOGLE_include_directive : require
// The V-cycle's small levels in one workgroup (gpu/device_multigrid.h): the coarse levels of at
// most kTailNodes nodes, whose passes would cost more to start than to run, and the coarsest,
// solved exactly.
//   kCoarseFactor  the coarsest level's matrix into `factor` (n x n, row by row, the lower
//                  triangle, n = 3 nodes <= kCoarsestDofs), then Cholesky's factor in place, column
//                  by column; a pivot that is not positive (a node no free particle reaches) is
//                  taken as 1, as the CPU's banded factor does (integrators/banded_cholesky.h)
//   kCoarseCycle   the cycle from the level in the push constants (its rhs restricted, its
//                  solution zero): on each level above the coarsest kCoarseSweeps sweeps of the 9
//                  colours ascending, the residual, its restriction; the coarsest level by the
//                  factor (L y = rhs, L^T x = y); back up, the prolongation and the sweeps with the
//                  colours descending (LatticeMultigrid::apply)
// The passes of a CG iteration return at once once the solve has stopped.
#include "gpu/shaders/shared_text.glsl"
#include "gpu/shaders/implicit_step.h"
#include "gpu/shaders/multigrid_step.h"

const uint kWorkgroupSize = kCoarseWorkgroup;
layout(local_size_x = kWorkgroupSize) in;

layout(std430, binding = 0) readonly buffer LevelBlocks { float level_blocks[]; };
layout(std430, binding = 1) readonly buffer LevelDiagonalInverse { Real level_diagonal_inverse[]; };  // [nodes][9]
layout(std430, binding = 2) buffer LevelRhs { Real level_rhs[]; };
layout(std430, binding = 3) buffer LevelSolution { Real level_solution[]; };
layout(std430, binding = 4) buffer LevelResidual { Real level_residual[]; };
layout(std430, binding = 5) buffer Factor { Real factor[]; };  // [kCoarsestDofs^2] at most
layout(std430, binding = 6) readonly buffer SolveUint { uint solve_uint[]; };

layout(push_constant) uniform Constants { MultigridPassConstants constants; };

#define CLOTHSIM_COARSE_LEVELS
#include "gpu/shaders/multigrid_levels.glsl"

shared Real unknowns[kCoarsestDofs];

// Every invocation's writes to the buffers and to `unknowns` seen by all of the workgroup.
void synchronize() {
  memoryBarrierBuffer();
  memoryBarrierShared();
  barrier();
}

// Entry (r, c) of a level's matrix, r >= c: unknown r = 3 node + component.
Real matrix_entry(Level level, uint r, uint c) {
  const uint node = r / 3u;
  const uint other = c / 3u;
  const int di = int(other / level.cols) - int(node / level.cols);
  const int dj = int(other % level.cols) - int(node % level.cols);
  if (abs(di) > 2 || abs(dj) > 2 || (abs(di) == 2 && abs(dj) == 2)) return Real(0.0);
  return level_block(level.base + node, stencil_slot(di, dj))[c % 3u][r % 3u];
}

void factorize(Level level) {
  const uint t = gl_LocalInvocationID.x;
  const uint n = 3u * node_count(level);
  for (uint index = t; index < n * n; index += kWorkgroupSize) {
    const uint r = index / n;
    const uint c = index % n;
    factor[index] = c <= r ? matrix_entry(level, r, c) : Real(0.0);
  }
  synchronize();
  for (uint k = 0u; k < n; ++k) {
    if (t == 0u) {
      const Real pivot = factor[k * n + k];
      factor[k * n + k] = pivot > Real(0.0) ? sqrt(pivot) : Real(1.0);
    }
    synchronize();
    const Real pivot = factor[k * n + k];
    for (uint i = k + 1u + t; i < n; i += kWorkgroupSize) factor[i * n + k] /= pivot;
    synchronize();
    for (uint i = k + 1u + t; i < n; i += kWorkgroupSize) {
      const Real lik = factor[i * n + k];
      for (uint j = k + 1u; j <= i; ++j) factor[i * n + j] -= lik * factor[j * n + k];
    }
    synchronize();
  }
}

// The coarsest level's solution from its rhs by the factor.
void solve_coarsest(Level level) {
  const uint t = gl_LocalInvocationID.x;
  const uint n = 3u * node_count(level);
  const uint first = 3u * level.base;
  for (uint i = t; i < n; i += kWorkgroupSize) unknowns[i] = level_rhs[first + i];
  synchronize();
  for (uint k = 0u; k < n; ++k) {  // L y = rhs
    if (t == 0u) unknowns[k] /= factor[k * n + k];
    synchronize();
    for (uint i = k + 1u + t; i < n; i += kWorkgroupSize) unknowns[i] -= factor[i * n + k] * unknowns[k];
    synchronize();
  }
  for (uint k = n; k > 0u; --k) {  // L^T x = y, row k - 1
    const uint row = k - 1u;
    if (t == 0u) unknowns[row] /= factor[row * n + row];
    synchronize();
    for (uint i = t; i < row; i += kWorkgroupSize) unknowns[i] -= factor[row * n + i] * unknowns[row];
    synchronize();
  }
  for (uint i = t; i < n; i += kWorkgroupSize) level_solution[first + i] = unknowns[i];
}

// kCoarseSweeps Gauss-Seidel sweeps over a coarse level's colours, ascending or descending.
void sweep(Level level, bool ascending) {
  for (uint sweep = 0u; sweep < kCoarseSweeps; ++sweep) {
    for (uint c = 0u; c < kSmootherColours; ++c) {
      const uint colour = ascending ? c : kSmootherColours - 1u - c;
      for (uint k = gl_LocalInvocationID.x; k < colour_nodes(level, colour); k += kWorkgroupSize) {
        coarse_smooth(level, colour_node(level, colour, k));
      }
      synchronize();
    }
  }
}

void cycle(Level first) {
  const uint t = gl_LocalInvocationID.x;
  Level levels[kMaxLevels];
  uint count = 1u;
  levels[0] = first;
  // Down to the coarsest.
  while (node_count(levels[count - 1u]) > kCoarsestNodes) {
    const Level level = levels[count - 1u];
    const Level next = coarser(level);
    sweep(level, true);
    for (uint node = t; node < node_count(level); node += kWorkgroupSize) store_coarse_residual(level, node);
    synchronize();
    for (uint node = t; node < node_count(next); node += kWorkgroupSize) restrict_to(level, next, node);
    synchronize();
    levels[count++] = next;
  }
  solve_coarsest(levels[count - 1u]);
  synchronize();
  // Up: the correction, then the sweeps in the reverse order.
  for (uint i = count - 1u; i > 0u; --i) {
    const Level level = levels[i - 1u];
    for (uint node = t; node < node_count(level); node += kWorkgroupSize) {
      set_level_solution(level.base + node,
                         level_vector3(kLevelSolution, level.base + node) + interpolated(level, levels[i], node));
    }
    synchronize();
    sweep(level, false);
  }
}

void main() {
  if (constants.iteration != 0u && solve_uint[kSolveDone] != 0u) return;
  const Level level = Level(constants.base, constants.rows, constants.cols);
  if (constants.phase == kCoarseFactor) {
    factorize(level);
  } else {
    cycle(level);
  }
}
