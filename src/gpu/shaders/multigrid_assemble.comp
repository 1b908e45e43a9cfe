#version 450
#extension GL_GOOGLE_include_directive : require
// The V-cycle's level 0 (gpu/device_multigrid.h): each free particle's row of implicit Euler's
// matrix A = M + h (C + drag) + h^2 K as blocks in the lattice's stencil, one invocation per
// particle (the CPU assembles the same row, BlockSystem::assemble, and its multigrid reads it).
// Each element the particle is in (the gather table's order, as the CPU sums a row) adds its block
// to each of its free particles; mass and drag join the diagonal. Anchored particles are outside
// the system: zero rows, and no blocks to them. Particles held on an obstacle's surface have their
// held directions filtered out of their rows and columns (S_p A_pq S_q, held_directions.h).
//
// Each free particle also offers its stiffness relative to its mass, (trace A_pp - 3 m) / m, to the
// largest over the sheet (BlockSystem::stiffness_ratio), which the host reads to choose between the
// V-cycle and block Jacobi for the solve. It is kept as a float's bits: a largest value does not
// depend on the order of the atomic operations, and non-negative floats order as their bits do.
#include "gpu/shaders/element_jacobian.glsl"
#include "gpu/shaders/implicit_step.h"
#include "gpu/shaders/multigrid_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer GatherOffset { uint gather_offset[]; };  // [particles + 1]
layout(std430, binding = 1) readonly buffer GatherSlot { uint gather_slot[]; };
layout(std430, binding = 2) readonly buffer ConnectorParticles { uint connector_particles[]; };
layout(std430, binding = 3) readonly buffer RadialParticles { uint radial_particles[]; };
layout(std430, binding = 4) readonly buffer ConnectorFactors { Real connector_factors[]; };
layout(std430, binding = 5) readonly buffer RadialFactors { Real radial_factors[]; };
layout(std430, binding = 6) readonly buffer Mass { Real particle_mass[]; };
layout(std430, binding = 7) readonly buffer Environment { Real environment[]; };  // gravity (3), drag
layout(std430, binding = 8) readonly buffer ParticleAnchor { int particle_anchor[]; };
layout(std430, binding = 9) readonly buffer SolveReal { Real solve_real[]; };
layout(std430, binding = 10) buffer SolveUint { uint solve_uint[]; };
layout(std430, binding = 11) readonly buffer Hold { uint hold[]; };  // [particles], kHold*
layout(std430, binding = 12) readonly buffer SurfaceContacts { Real surface_contacts[]; };
layout(std430, binding = 13) buffer LevelBlocks { float level_blocks[]; };

layout(push_constant) uniform Constants { MultigridPassConstants constants; };

#include "gpu/shaders/implicit_factors.glsl"
#include "gpu/shaders/held_directions.glsl"
#include "gpu/shaders/multigrid_levels.glsl"

// S_p: the directions the step solves for at particle p (I, I - n n^T, or none).
Mat3 solved_directions(uint p) {
  const uint how = hold[p];
  if (how == kHoldNone) return Mat3(1.0);
  if (how == kHoldAll) return Mat3(0.0);
  const Vec3 n = contact_normal(p);
  return Mat3(1.0) - outerProduct(n, n);
}

// The stencil slot of particle q in particle p's row.
int slot_of(uint p, uint q) {
  const uint cols = constants.cols;
  return stencil_slot(int(q / cols) - int(p / cols), int(q % cols) - int(p % cols));
}

void main() {
  const uint p = invocation_index();
  if (p >= constants.rows * constants.cols) return;
  Mat3 row[kStencilSlots];
  for (int s = 0; s < kStencilSlots; ++s) row[s] = Mat3(0.0);
  if (particle_anchor[p] < 0) {
    const Real stiffness_scale = solve_real[kStiffnessScale];
    const Real damping_scale = solve_real[kDampingScale];
    for (uint k = gather_offset[p]; k < gather_offset[p + 1]; ++k) {
      const uint slot = gather_slot[k];
      if (slot < constants.radial_slot_base) {
        const uint e = slot / 2u;
        const Mat3 block = connector_diagonal(load_connector(e), stiffness_scale, damping_scale);
        for (uint j = 0u; j < 2u; ++j) {
          const uint q = connector_particles[2u * e + j];
          if (particle_anchor[q] >= 0) continue;
          row[slot_of(p, q)] += j == slot % 2u ? block : -block;
        }
      } else {
        const uint local = slot - constants.radial_slot_base;
        const uint r = local / 3u;
        const RadialLinearization f = load_radial(r);
        for (uint j = 0u; j < 3u; ++j) {
          const uint q = radial_particles[3u * r + j];
          if (particle_anchor[q] >= 0) continue;
          row[slot_of(p, q)] += radial_block(f, local % 3u, j, stiffness_scale, damping_scale);
        }
      }
    }
    const Real mass = particle_mass[p];
    row[kStencilDiagonal] += (mass + damping_scale * environment[3]) * Mat3(1.0);
    const Mat3 diagonal = row[kStencilDiagonal];
    const Real ratio = (diagonal[0][0] + diagonal[1][1] + diagonal[2][2] - Real(3.0) * mass) / mass;
    atomicMax(solve_uint[kStiffnessRatio], floatBitsToUint(float(max(ratio, Real(0.0)))));
    if (solve_uint[kHolding] != 0u) {
      const Mat3 rows_solved = solved_directions(p);
      for (int s = 0; s < kStencilSlots; ++s) {
        uint q;
        if (!stencil_neighbour(p / constants.cols, p % constants.cols, s, constants.rows, constants.cols, q)) continue;
        row[s] = rows_solved * row[s] * solved_directions(q);
      }
    }
  }
  for (int s = 0; s < kStencilSlots; ++s) {
    const uint i = block_index(p, s);
    for (uint column = 0u; column < 3u; ++column) {
      for (uint r = 0u; r < 3u; ++r) level_blocks[i + 3u * column + r] = float(row[s][column][r]);
    }
  }
}
