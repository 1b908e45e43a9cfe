#version 450
#extension GL_GOOGLE_include_directive : require
// The V-cycle's coarsest level solved exactly (gpu/device_multigrid.h), by one workgroup: at most
// kCoarsestDofs unknowns (LatticeMultigrid::kCoarsestNodes nodes of 3), few enough that a dense
// factor costs less than a pass over the lattice.
//   kCoarsestFactor  the level's matrix into `factor` (n x n, row by row, the lower triangle), then
//                    Cholesky's factor in place, column by column; a pivot that is not positive (a
//                    node no free particle reaches) is taken as 1, as the CPU's banded factor does
//   kCoarsestSolve   the level's solution from its right-hand side: L y = rhs, then L^T x = y
// The passes of a CG iteration return at once once the solve has stopped.
#include "gpu/shaders/shared_text.glsl"
#include "gpu/shaders/implicit_step.h"
#include "gpu/shaders/multigrid_step.h"

const uint kWorkgroupSize = kCoarsestWorkgroup;
layout(local_size_x = kWorkgroupSize) in;

layout(std430, binding = 0) readonly buffer LevelBlocks { Real level_blocks[]; };
layout(std430, binding = 1) buffer Factor { Real factor[]; };  // [kCoarsestDofs^2] at most
layout(std430, binding = 2) readonly buffer LevelRhs { Real level_rhs[]; };
layout(std430, binding = 3) writeonly buffer LevelSolution { Real level_solution[]; };
layout(std430, binding = 4) readonly buffer SolveUint { uint solve_uint[]; };

layout(push_constant) uniform Constants { MultigridPassConstants constants; };

#include "gpu/shaders/multigrid_levels.glsl"

shared Real unknowns[kCoarsestDofs];

// Every invocation's writes to `factor` and `unknowns` seen by all of the workgroup.
void synchronize() {
  memoryBarrierBuffer();
  memoryBarrierShared();
  barrier();
}

// Entry (r, c) of the level's matrix, r >= c: unknown r = 3 node + component.
Real matrix_entry(uint r, uint c) {
  const uint node = r / 3u;
  const uint other = c / 3u;
  const int di = int(other / constants.cols) - int(node / constants.cols);
  const int dj = int(other % constants.cols) - int(node % constants.cols);
  if (abs(di) > 2 || abs(dj) > 2 || (abs(di) == 2 && abs(dj) == 2)) return Real(0.0);
  return level_block(constants.base + node, stencil_slot(di, dj))[c % 3u][r % 3u];
}

void factorize(uint n) {
  const uint t = gl_LocalInvocationID.x;
  for (uint index = t; index < n * n; index += kWorkgroupSize) {
    const uint r = index / n;
    const uint c = index % n;
    factor[index] = c <= r ? matrix_entry(r, c) : Real(0.0);
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

void solve(uint n) {
  const uint t = gl_LocalInvocationID.x;
  const uint first = 3u * constants.base;
  for (uint i = t; i < n; i += kWorkgroupSize) unknowns[i] = level_rhs[first + i];
  synchronize();
  for (uint k = 0u; k < n; ++k) {  // L y = rhs
    if (t == 0u) unknowns[k] /= factor[k * n + k];
    synchronize();
    for (uint i = k + 1u + t; i < n; i += kWorkgroupSize) unknowns[i] -= factor[i * n + k] * unknowns[k];
    synchronize();
  }
  for (uint k = n; k-- > 0u;) {  // L^T x = y
    if (t == 0u) unknowns[k] /= factor[k * n + k];
    synchronize();
    for (uint i = t; i < k; i += kWorkgroupSize) unknowns[i] -= factor[k * n + i] * unknowns[k];
    synchronize();
  }
  for (uint i = t; i < n; i += kWorkgroupSize) level_solution[first + i] = unknowns[i];
}

void main() {
  if (constants.iteration != 0u && solve_uint[kSolveDone] != 0u) return;
  const uint n = 3u * constants.rows * constants.cols;
  if (constants.phase == kCoarsestFactor) {
    factorize(n);
  } else {
    solve(n);
  }
}
