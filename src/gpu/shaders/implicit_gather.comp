#version 450
#extension GL_GOOGLE_include_directive : require
// Each particle's row of a product with implicit Euler's matrix: its element slots
// (implicit_product) in the gather table's order, plus the mass and the drag on the diagonal, and
// what the conjugate gradients make of it (the mode, implicit_step.h):
//   kGatherRightHandSide  b = h (f0 - K z)  (ImplicitEuler::form_rhs)
//   kGatherResidual       r = b - A u, z = P^-1 r, the first direction p = z; partials r.z, r.r, b.b
//   kGatherProduct        q = A p; partial p.q
//   kGatherImpulse        a held particle's surface impulse A dv - b (its normal part where held
//                         along the normal; ImplicitEuler::book_surface_impulses), zero elsewhere
// Anchored particles are outside the system: zero rows, residuals and directions. Particles held on
// an obstacle's surface (implicit_diagonal) have their held directions filtered out of r, z and q
// (held_directions.glsl). Each workgroup writes its partial sums for implicit_reduce.
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
layout(std430, binding = 17) readonly buffer Hold { uint hold[]; };  // [particle_count], kHold*
layout(std430, binding = 18) readonly buffer SurfaceContacts { Real surface_contacts[]; };  // [particles][kContactReals]
layout(std430, binding = 19) writeonly buffer Impulse { Real impulse[]; };  // [3 particle_count], N s

layout(push_constant) uniform Constants { ImplicitPassConstants constants; };

#include "gpu/shaders/workgroup_sums.glsl"
#include "gpu/shaders/held_directions.glsl"


// The arrays load() reads and store() writes.
const uint kReadRhs = 0u, kReadSolution = 1u, kReadDirection = 2u, kReadForce = 3u;
const uint kWriteRhs = 0u, kWriteResidual = 1u, kWritePreconditioned = 2u, kWriteDirection = 3u, kWriteProduct = 4u,
           kWriteImpulse = 5u;

Vec3 load(uint p, uint array) {
  const uint i = 3 * p;
  if (array == kReadRhs) return Vec3(rhs[i], rhs[i + 1], rhs[i + 2]);
  if (array == kReadSolution) return Vec3(solution[i], solution[i + 1], solution[i + 2]);
  if (array == kReadDirection) return Vec3(direction[i], direction[i + 1], direction[i + 2]);
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
    if (array == kWriteRhs) rhs[i + k] = v[k];
    if (array == kWriteResidual) residual[i + k] = v[k];
    if (array == kWritePreconditioned) preconditioned[i + k] = v[k];
    if (array == kWriteDirection) direction[i + k] = v[k];
    if (array == kWriteProduct) product[i + k] = v[k];
    if (array == kWriteImpulse) impulse[i + k] = v[k];
  }
}

void main() {
  if (constants.iteration != 0u && solve_uint[kSolveDone] != 0u) return;
  const uint p = invocation_index();
  const bool inside = p < constants.particle_count;
  const bool free = inside && particle_anchor[p] < 0;
  Real partial[3] = Real[3](Real(0.0), Real(0.0), Real(0.0));
  if (inside) {
    // The diagonal's mass and drag, then the element slots (zero rows where anchored).
    const Real diagonal = particle_mass[p] + solve_real[kDampingScale] * environment[3];
    if (constants.phase == kGatherRightHandSide) {
      const Real h = solve_real[kImplicitStep];
      store(p, free ? h * (load(p, kReadForce) - slot_sum(p)) : Vec3(0.0), kWriteRhs);
    } else if (constants.phase == kGatherResidual) {
      // direction holds the unknown's current value u here (implicit_setup's warm start).
      const Vec3 b = load(p, kReadRhs);
      const Vec3 r = free ? held(p, b - (diagonal * load(p, kReadDirection) + slot_sum(p))) : Vec3(0.0);
      const Vec3 z = free ? held(p, jacobi_block(p) * r) : Vec3(0.0);
      store(p, r, kWriteResidual);
      store(p, z, kWritePreconditioned);
      store(p, z, kWriteDirection);  // the first direction
      partial[0] = dot(r, z);
      partial[1] = dot(r, r);
      // The target is relative to the whole right-hand side, held directions included (as on the CPU).
      partial[2] = dot(b, b);
    } else if (constants.phase == kGatherProduct) {
      const Vec3 direction_p = load(p, kReadDirection);
      const Vec3 q = free ? held(p, diagonal * direction_p + slot_sum(p)) : Vec3(0.0);
      store(p, q, kWriteProduct);
      partial[0] = dot(direction_p, q);
    } else {
      // direction holds dv here.
      const uint how = free ? hold[p] : kHoldNone;
      Vec3 surface = Vec3(0.0);
      if (how != kHoldNone) {
        surface = diagonal * load(p, kReadDirection) + slot_sum(p) - load(p, kReadRhs);
        if (how == kHoldNormal) surface = dot(contact_normal(p), surface) * contact_normal(p);
      }
      store(p, surface, kWriteImpulse);
    }
  }
  if (constants.phase == kGatherRightHandSide || constants.phase == kGatherImpulse) return;
  sum_over_workgroup(partial);
  if (gl_LocalInvocationID.x == 0u) {
    const uint block = workgroup_index();
    for (uint k = 0u; k < 3u; ++k) block_sums[3 * block + k] = workgroup_sum[k][0];
  }
}
