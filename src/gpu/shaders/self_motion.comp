#version 450
#extension GL_GOOGLE_include_directive : require
// How far the particles move, for self-collision's decision to keep its candidates
// (gpu/device_self_contacts.h, SelfContacts::refresh_candidates on the CPU): the largest squared
// distance of a particle's start or end position from where the candidates were found, and the
// largest squared motion start -> end. Two passes: each workgroup's maxima, then one workgroup's
// over those. A maximum is the same in any order.
#include "gpu/shaders/shared_text.glsl"
#include "gpu/shaders/self_step.h"

const uint kWorkgroupSize = kMotionWorkgroup;
layout(local_size_x = kMotionWorkgroup) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Start { Real start[]; };  // [particles][3]
layout(std430, binding = 1) readonly buffer End { Real end[]; };
layout(std430, binding = 2) readonly buffer FoundAt { Real found_at[]; };  // [particles][3]
layout(std430, binding = 3) buffer BlockMotion { Real block_motion[]; };   // [blocks][kMotionValues]
layout(std430, binding = 4) writeonly buffer Motion { Real motion[]; };    // [kMotionValues]

layout(push_constant) uniform Constants { MotionPassConstants constants; };

shared Real largest[kMotionValues][kMotionWorkgroup];

Vec3 at(uint p, uint which) {
  if (which == 0u) return Vec3(start[3u * p], start[3u * p + 1u], start[3u * p + 2u]);
  if (which == 1u) return Vec3(end[3u * p], end[3u * p + 1u], end[3u * p + 2u]);
  return Vec3(found_at[3u * p], found_at[3u * p + 1u], found_at[3u * p + 2u]);
}
Real squared(Vec3 v) { return dot(v, v); }

// Each value's maximum over the workgroup, into largest[*][0].
void reduce_workgroup() {
  const uint i = gl_LocalInvocationID.x;
  for (uint stride = kMotionWorkgroup / 2u; stride > 0u; stride /= 2u) {
    barrier();
    if (i < stride) {
      for (uint v = 0u; v < kMotionValues; ++v) largest[v][i] = max(largest[v][i], largest[v][i + stride]);
    }
  }
  barrier();
}

void main() {
  const uint i = gl_LocalInvocationID.x;
  if (constants.phase == kMotionBlocks) {
    const uint p = invocation_index();
    Real from_found = Real(0.0);
    Real of_step = Real(0.0);
    if (p < constants.particles) {
      const Vec3 a = at(p, 0u);
      const Vec3 b = at(p, 1u);
      const Vec3 f = at(p, 2u);
      from_found = max(squared(b - f), squared(a - f));
      of_step = squared(b - a);
    }
    largest[kMotionFromFound][i] = from_found;
    largest[kMotionOfStep][i] = of_step;
    reduce_workgroup();
    if (i == 0u) {
      for (uint v = 0u; v < kMotionValues; ++v) block_motion[kMotionValues * workgroup_index() + v] = largest[v][0];
    }
  } else {
    for (uint v = 0u; v < kMotionValues; ++v) largest[v][i] = Real(0.0);
    for (uint b = i; b < constants.blocks; b += kMotionWorkgroup) {
      for (uint v = 0u; v < kMotionValues; ++v) largest[v][i] = max(largest[v][i], block_motion[kMotionValues * b + v]);
    }
    reduce_workgroup();
    if (i == 0u) {
      for (uint v = 0u; v < kMotionValues; ++v) motion[v] = largest[v][0];
    }
  }
}
