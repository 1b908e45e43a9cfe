#version 450
#extension GL_GOOGLE_include_directive : require
// Implicit Euler's per-particle steps around the solve (ImplicitEuler::step on the CPU), one
// invocation per particle, by phase (implicit_step.h):
//   kSetupDisplacement  direction = z: h v for a free particle, its path's displacement over the step
//                       for an anchored one, whose velocity change is known (path velocity - v)
//   kSetupWarmStart     direction = dv, the unknown's current value: CG starts from the last step's
//   kSetupCheck         the first free particle whose dv is not finite
//   kSetupUpdate        unless one is: v += dv, x += h v; anchored particles on their paths
//   kSetupPowers        at the step's end (forces evaluated there): each workgroup's drag and anchor
//                       power, and the first workgroup the springs' damping power (DeviceForces' sum)
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/implicit_step.h"

const uint kWorkgroupSize = kImplicitReduceWorkgroup;
layout(local_size_x = kWorkgroupSize) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) buffer Position { Real position[]; };  // [3 particle_count], m
layout(std430, binding = 1) buffer Velocity { Real velocity[]; };  // [3 particle_count], m/s
layout(std430, binding = 2) readonly buffer Force { Real force[]; };  // [3 particle_count], N
layout(std430, binding = 3) readonly buffer Mass { Real particle_mass[]; };
layout(std430, binding = 4) readonly buffer Environment { Real environment[]; };  // gravity (3), drag (kg/s; 0 when off)
layout(std430, binding = 5) readonly buffer ParticleAnchor { int particle_anchor[]; };
layout(std430, binding = 6) readonly buffer AnchorRows { Real anchor_rows[]; };  // [anchors][kAnchorRowReals]
layout(std430, binding = 7) buffer Solution { Real solution[]; };
layout(std430, binding = 8) writeonly buffer Direction { Real direction[]; };
layout(std430, binding = 9) readonly buffer DampingPower { Real damping_power[]; };  // [1], W
layout(std430, binding = 10) writeonly buffer BlockSums { Real block_sums[]; };  // [workgroups][3]
layout(std430, binding = 11) readonly buffer SolveReal { Real solve_real[]; };
layout(std430, binding = 12) buffer SolveUint { uint solve_uint[]; };

layout(push_constant) uniform Constants { ImplicitPassConstants constants; };

#include "gpu/shaders/workgroup_sums.glsl"

// The arrays read3() reads and write3() writes.
const uint kReadPosition = 0u, kReadVelocity = 1u, kReadForce = 2u, kReadSolution = 3u;
const uint kWritePosition = 0u, kWriteVelocity = 1u, kWriteSolution = 2u, kWriteDirection = 3u;

Vec3 read3(uint p, uint array) {
  const uint i = 3 * p;
  if (array == kReadPosition) return Vec3(position[i], position[i + 1], position[i + 2]);
  if (array == kReadVelocity) return Vec3(velocity[i], velocity[i + 1], velocity[i + 2]);
  if (array == kReadForce) return Vec3(force[i], force[i + 1], force[i + 2]);
  return Vec3(solution[i], solution[i + 1], solution[i + 2]);
}

// Row `row`'s path position (kPathPosition), velocity or acceleration at the step's end.
const uint kPathPosition = 0u, kPathVelocity = 1u, kPathAcceleration = 2u;
Vec3 anchor_value(int row, uint which) {
  const uint i = kAnchorRowReals * uint(row) + 3u * which;
  return Vec3(anchor_rows[i], anchor_rows[i + 1], anchor_rows[i + 2]);
}

void write3(uint p, Vec3 v, uint array) {
  for (uint k = 0u; k < 3u; ++k) {
    if (array == kWritePosition) position[3 * p + k] = v[k];
    if (array == kWriteVelocity) velocity[3 * p + k] = v[k];
    if (array == kWriteSolution) solution[3 * p + k] = v[k];
    if (array == kWriteDirection) direction[3 * p + k] = v[k];
  }
}

void powers(uint p) {
  Real partial[3] = Real[3](Real(0.0), Real(0.0), Real(0.0));
  if (p < constants.particle_count) {
    if (p == 0u) partial[0] = damping_power[0];
    const Vec3 v = read3(p, kReadVelocity);
    partial[1] = -environment[3] * dot(v, v);
    const int row = particle_anchor[p];
    // The force the anchor exerts to keep its particle on the path, m a - f, times its velocity.
    if (row >= 0) partial[2] = dot(v, particle_mass[p] * anchor_value(row, kPathAcceleration) - read3(p, kReadForce));
  }
  sum_over_workgroup(partial);
  if (gl_LocalInvocationID.x == 0u) {
    const uint block = workgroup_index();
    for (uint k = 0u; k < 3u; ++k) block_sums[3 * block + k] = workgroup_sum[k][0];
  }
}

void main() {
  const uint p = invocation_index();
  if (constants.phase == kSetupPowers) {
    powers(p);
    return;
  }
  if (p >= constants.particle_count) return;
  const int row = particle_anchor[p];
  const Real h = solve_real[kImplicitStep];
  if (constants.phase == kSetupDisplacement) {
    if (row < 0) {
      write3(p, h * read3(p, kReadVelocity), kWriteDirection);
    } else {
      write3(p, anchor_value(row, kPathPosition) - read3(p, kReadPosition), kWriteDirection);
      write3(p, anchor_value(row, kPathVelocity) - read3(p, kReadVelocity), kWriteSolution);
    }
  } else if (constants.phase == kSetupWarmStart) {
    write3(p, read3(p, kReadSolution), kWriteDirection);
  } else if (constants.phase == kSetupCheck) {
    const Vec3 dv = read3(p, kReadSolution);
    if (row < 0 && (any(isnan(dv)) || any(isinf(dv)))) atomicMin(solve_uint[kNonFiniteParticle], p);
  } else if (solve_uint[kNonFiniteParticle] == kNoParticle) {
    if (row < 0) {
      const Vec3 v = read3(p, kReadVelocity) + read3(p, kReadSolution);
      write3(p, v, kWriteVelocity);
      write3(p, read3(p, kReadPosition) + h * v, kWritePosition);
    } else {
      write3(p, anchor_value(row, kPathPosition), kWritePosition);
      write3(p, anchor_value(row, kPathVelocity), kWriteVelocity);
    }
  }
}
