#version 450
#extension GL_GOOGLE_include_directive : require
// The V-cycle's passes on one level of more than kTailNodes nodes (gpu/device_multigrid.h;
// LatticeMultigrid::apply on the CPU), one invocation per node:
//   kCycleClear     level 0's solution (the preconditioned residual z) = 0, where the cycle starts
//   kCycleSmooth    one colour of a Gauss-Seidel sweep, one invocation per node of the colour:
//                   x += D^-1 (rhs - A x) (level 0: the held directions filtered out, anchored
//                   particles left out). Colours ascending down the V and descending up it, so the
//                   cycle is symmetric, as conjugate gradients require
//   kCycleResidual  the level's residual rhs - A x (zero where anchored)
//   kCycleRestrict  one invocation per node of the next level: its rhs = P^T residual, its solution 0
//   kCycleProlong   x += P (the next level's solution) (level 0: filtered, anchored particles left out)
// Level 0's rhs and solution are the conjugate gradients' residual r and preconditioned residual z,
// its smoother's blocks implicit Euler's block Jacobi inverses. The passes of a CG iteration return
// at once once the solve has stopped.
#include "gpu/shaders/shared_text.glsl"
#include "gpu/shaders/implicit_step.h"
#include "gpu/shaders/multigrid_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer LevelBlocks { float level_blocks[]; };
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
#define CLOTHSIM_COARSE_LEVELS
#include "gpu/shaders/multigrid_levels.glsl"

// Level 0, the lattice: the CG's vectors, implicit Euler's smoother blocks, anchors and holds.

Vec3 fine_rhs(uint p) { return Vec3(residual[3u * p], residual[3u * p + 1u], residual[3u * p + 2u]); }
Vec3 fine_solution(uint p) {
  return Vec3(preconditioned[3u * p], preconditioned[3u * p + 1u], preconditioned[3u * p + 2u]);
}
void set_fine_solution(uint p, Vec3 z) {
  for (uint k = 0u; k < 3u; ++k) preconditioned[3u * p + k] = z[k];
}

// rhs - A z at particle p (level 0's matrix is filtered in the held directions, multigrid_assemble).
Vec3 fine_residual(Level level, uint p) {
  const uint i = p / level.cols;
  const uint j = p % level.cols;
  Vec3 product = Vec3(0.0);
  for (int s = 0; s < kStencilSlots; ++s) {
    uint q;
    if (stencil_neighbour(i, j, s, level.rows, level.cols, q)) product += level_block(p, s) * fine_solution(q);
  }
  return fine_rhs(p) - product;
}

Mat3 jacobi_block(uint p) {
  const uint i = 9u * p;
  return Mat3(jacobi[i], jacobi[i + 1], jacobi[i + 2], jacobi[i + 3], jacobi[i + 4], jacobi[i + 5], jacobi[i + 6],
              jacobi[i + 7], jacobi[i + 8]);
}

bool anchored(uint p) { return particle_anchor[p] >= 0; }

void main() {
  if (constants.iteration != 0u && solve_uint[kSolveDone] != 0u) return;
  const Level level = Level(constants.base, constants.rows, constants.cols);
  const Level next = Level(constants.next_base, constants.next_rows, constants.next_cols);
  const bool fine = constants.level == 0u;
  const uint k = invocation_index();
  if (constants.phase == kCycleSmooth) {
    if (k >= colour_nodes(level, constants.colour)) return;
    const uint node = colour_node(level, constants.colour, k);
    if (!fine) {
      coarse_smooth(level, node);
    } else if (!anchored(node)) {
      set_fine_solution(node, fine_solution(node) + held(node, jacobi_block(node) * fine_residual(level, node)));
    }
  } else if (constants.phase == kCycleRestrict) {
    if (k < node_count(next)) restrict_to(level, next, k);
  } else if (k < node_count(level)) {
    if (constants.phase == kCycleClear) {
      set_fine_solution(k, Vec3(0.0));
    } else if (constants.phase == kCycleResidual && !fine) {
      store_coarse_residual(level, k);
    } else if (constants.phase == kCycleResidual) {
      const Vec3 r = anchored(k) ? Vec3(0.0) : fine_residual(level, k);
      for (uint c = 0u; c < 3u; ++c) level_residual[3u * k + c] = r[c];
    } else if (!fine) {
      set_level_solution(level.base + k, level_vector3(kLevelSolution, level.base + k) + interpolated(level, next, k));
    } else if (!anchored(k)) {
      set_fine_solution(k, fine_solution(k) + held(k, interpolated(level, next, k)));
    }
  }
}
