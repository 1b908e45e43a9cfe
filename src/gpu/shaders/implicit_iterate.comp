#version 450
#extension GL_GOOGLE_include_directive : require
// The conjugate gradients' vector updates on the device (BlockSystem::solve), one invocation per
// particle, the anchored ones left out:
//   kIterateUpdate     u += alpha p, r -= alpha q, z = P^-1 r (its held directions filtered out);
//                      each workgroup's partial r.z and r.r
//   kIterateDirection  p = z + beta p
// and, with the V-cycle (gpu/device_multigrid.h) for P^-1:
//   kIterateAdvance    u += alpha p, r -= alpha q (the V-cycle then makes z)
//   kIterateStart      after the first residual's V-cycle: the first direction p = z; partials r.z, r.r, b.b
//   kIterateSums       after an iteration's V-cycle: partials r.z, r.r
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/implicit_step.h"

const uint kWorkgroupSize = kImplicitReduceWorkgroup;
layout(local_size_x = kWorkgroupSize) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) buffer Solution { Real solution[]; };
layout(std430, binding = 1) buffer Residual { Real residual[]; };
layout(std430, binding = 2) buffer Preconditioned { Real preconditioned[]; };
layout(std430, binding = 3) buffer Direction { Real direction[]; };
layout(std430, binding = 4) readonly buffer Product { Real product[]; };
layout(std430, binding = 5) readonly buffer Jacobi { Real jacobi[]; };  // [particle_count][9], column by column
layout(std430, binding = 6) readonly buffer ParticleAnchor { int particle_anchor[]; };
layout(std430, binding = 7) writeonly buffer BlockSums { Real block_sums[]; };  // [workgroups][3]
layout(std430, binding = 8) readonly buffer SolveReal { Real solve_real[]; };
layout(std430, binding = 9) readonly buffer SolveUint { uint solve_uint[]; };
layout(std430, binding = 10) readonly buffer Hold { uint hold[]; };  // [particle_count], kHold*
layout(std430, binding = 11) readonly buffer SurfaceContacts { Real surface_contacts[]; };  // [particles][kContactReals]
layout(std430, binding = 12) readonly buffer Rhs { Real rhs[]; };

layout(push_constant) uniform Constants { ImplicitPassConstants constants; };

#include "gpu/shaders/workgroup_sums.glsl"
#include "gpu/shaders/held_directions.glsl"

Mat3 jacobi_block(uint p) {
  const uint i = 9 * p;
  return Mat3(jacobi[i], jacobi[i + 1], jacobi[i + 2], jacobi[i + 3], jacobi[i + 4], jacobi[i + 5], jacobi[i + 6],
              jacobi[i + 7], jacobi[i + 8]);
}

// u += alpha p, r -= alpha q at a free particle; returns r.
Vec3 advance(uint p) {
  const Real alpha = solve_real[kAlpha];
  Vec3 r;
  for (uint k = 0u; k < 3u; ++k) {
    solution[3 * p + k] += alpha * direction[3 * p + k];
    r[k] = residual[3 * p + k] - alpha * product[3 * p + k];
    residual[3 * p + k] = r[k];
  }
  return r;
}

void main() {
  if (solve_uint[kSolveDone] != 0u) return;
  const uint p = invocation_index();
  const bool free = p < constants.particle_count && particle_anchor[p] < 0;
  if (constants.phase == kIterateDirection) {
    if (!free) return;
    const Real beta = solve_real[kBeta];
    for (uint k = 3 * p; k < 3 * p + 3; ++k) direction[k] = preconditioned[k] + beta * direction[k];
    return;
  }
  if (constants.phase == kIterateAdvance) {
    if (free) advance(p);
    return;
  }
  Real partial[3] = Real[3](Real(0.0), Real(0.0), Real(0.0));
  if (free && constants.phase == kIterateUpdate) {
    const Vec3 r = advance(p);
    const Vec3 z = held(p, jacobi_block(p) * r);
    for (uint k = 0u; k < 3u; ++k) preconditioned[3 * p + k] = z[k];
    partial[0] = dot(r, z);
    partial[1] = dot(r, r);
  } else if (free) {
    Vec3 r, z, b;
    for (uint k = 0u; k < 3u; ++k) {
      r[k] = residual[3 * p + k];
      z[k] = preconditioned[3 * p + k];
      b[k] = rhs[3 * p + k];
      if (constants.phase == kIterateStart) direction[3 * p + k] = z[k];
    }
    partial[0] = dot(r, z);
    partial[1] = dot(r, r);
    partial[2] = constants.phase == kIterateStart ? dot(b, b) : Real(0.0);
  }
  sum_over_workgroup(partial);
  if (gl_LocalInvocationID.x == 0u) {
    const uint block = workgroup_index();
    for (uint k = 0u; k < 3u; ++k) block_sums[3 * block + k] = workgroup_sum[k][0];
  }
}
