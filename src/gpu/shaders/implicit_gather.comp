#version 450
#extension GL_GOOGLE_include_directive : require
// Each particle's row of a product with implicit Euler's matrix: its element slots
// (implicit_product) in the gather table's order, plus the mass and the drag on the diagonal, and
// what the conjugate gradients make of it (the mode, implicit_step.h):
//   kGatherRightHandSide  b = h (f0 - K z)  (ImplicitEuler::form_rhs)
//   kGatherResidual       r = b - A u, z = P^-1 r, the first direction p = z; partials r.z, r.r, b.b
//   kGatherProduct        q = A p; partial p.q
// Anchored particles are outside the system: zero rows, residuals and directions. Each workgroup
// writes its partial sums for implicit_reduce.
#include "gpu/shaders/element_jacobian.glsl"
#include "gpu/shaders/implicit_step.h"

const uint kWorkgroupSize = kImplicitReduceWorkgroup;
layout(local_size_x = kWorkgroupSize) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer GatherOffset { uint gather_offset[]; };  // [particle_count + 1]
layout(std430, binding = 1) readonly buffer GatherSlot { uint gather_slot[]; };
layout(std430, binding = 2) readonly buffer SlotForce { Real slot_force[]; };  // the products' slots
layout(std430, binding = 3) readonly buffer Mass { Real particle_mass[]; };  // kg
layout(std430, binding = 4) readonly buffer Environment { Real environment[]; };  // gravity (3), drag (kg/s; 0 when off)
layout(std430, binding = 5) readonly buffer Force { Real force[]; };  // [3 particle_count], f0, N
layout(std430, binding = 6) readonly buffer ParticleAnchor { int particle_anchor[]; };  // anchor row or -1
layout(std430, binding = 7) buffer Rhs { Real rhs[]; };
layout(std430, binding = 8) readonly buffer Solution { Real solution[]; };
layout(std430, binding = 9) writeonly buffer Residual { Real residual[]; };
layout(std430, binding = 10) writeonly buffer Preconditioned { Real preconditioned[]; };
layout(std430, binding = 11) buffer Direction { Real direction[]; };
layout(std430, binding = 12) writeonly buffer Product { Real product[]; };
layout(std430, binding = 13) readonly buffer Jacobi { Real jacobi[]; };  // [particle_count][9], inverse diagonal blocks
layout(std430, binding = 14) writeonly buffer BlockSums { Real block_sums[]; };  // [workgroups][3]
layout(std430, binding = 15) readonly buffer SolveReal { Real solve_real[]; };
layout(std430, binding = 16) readonly buffer SolveUint { uint solve_uint[]; };

layout(push_constant) uniform Constants { ImplicitPassConstants constants; };

#include "gpu/shaders/workgroup_sums.glsl"

Vec3 load(uint p, uint array) {
  const uint i = 3 * p;
  if (array == 0u) return Vec3(rhs[i], rhs[i + 1], rhs[i + 2]);
  if (array == 1u) return Vec3(solution[i], solution[i + 1], solution[i + 2]);
  if (array == 2u) return Vec3(direction[i], direction[i + 1], direction[i + 2]);
  return Vec3(force[i], force[i + 1], force[i + 2]);
}

Vec3 slot_sum(uint p) {
  Vec3 sum = Vec3(0.0);
  for (uint k = gather_offset[p]; k < gather_offset[p + 1]; ++k) {
    const uint slot = gather_slot[k];
    sum += Vec3(slot_force[3 * slot], slot_force[3 * slot + 1], slot_force[3 * slot + 2]);
  }
  return sum;
}

Mat3 jacobi_block(uint p) {
  const uint i = 9 * p;
  return Mat3(jacobi[i], jacobi[i + 1], jacobi[i + 2], jacobi[i + 3], jacobi[i + 4], jacobi[i + 5], jacobi[i + 6],
              jacobi[i + 7], jacobi[i + 8]);
}

void store(uint p, Vec3 v, uint array) {
  const uint i = 3 * p;
  for (uint k = 0u; k < 3u; ++k) {
    if (array == 0u) rhs[i + k] = v[k];
    if (array == 1u) residual[i + k] = v[k];
    if (array == 2u) preconditioned[i + k] = v[k];
    if (array == 3u) direction[i + k] = v[k];
    if (array == 4u) product[i + k] = v[k];
  }
}

void main() {
  if (solve_uint[kSolveDone] != 0u) return;
  const uint p = invocation_index();
  const bool inside = p < constants.particle_count;
  const bool free = inside && particle_anchor[p] < 0;
  Real partial[3] = Real[3](Real(0.0), Real(0.0), Real(0.0));
  if (inside) {
    // The diagonal's mass and drag, then the element slots (zero rows where anchored).
    const Real diagonal = particle_mass[p] + solve_real[kDampingScale] * environment[3];
    if (constants.phase == kGatherRightHandSide) {
      const Real h = solve_real[kImplicitStep];
      store(p, free ? h * (load(p, 3u) - slot_sum(p)) : Vec3(0.0), 0u);
    } else if (constants.phase == kGatherResidual) {
      // direction holds the unknown's current value u here (implicit_setup's warm start).
      const Vec3 b = load(p, 0u);
      const Vec3 r = free ? b - (diagonal * load(p, 2u) + slot_sum(p)) : Vec3(0.0);
      const Vec3 z = free ? jacobi_block(p) * r : Vec3(0.0);
      store(p, r, 1u);
      store(p, z, 2u);
      store(p, z, 3u);
      partial[0] = dot(r, z);
      partial[1] = dot(r, r);
      partial[2] = dot(b, b);
    } else {
      const Vec3 direction_p = load(p, 2u);
      const Vec3 q = free ? diagonal * direction_p + slot_sum(p) : Vec3(0.0);
      store(p, q, 4u);
      partial[0] = dot(direction_p, q);
    }
  }
  if (constants.phase == kGatherRightHandSide) return;
  sum_over_workgroup(partial);
  if (gl_LocalInvocationID.x == 0u) {
    const uint block = workgroup_index();
    for (uint k = 0u; k < 3u; ++k) block_sums[3 * block + k] = workgroup_sum[k][0];
  }
}
