#version 450
#extension GL_GOOGLE_include_directive : require
// Self-collision's detection on the device (gpu/device_self_candidates.h), stages 2 and 3's tests
// of the CPU's self pass (SelfContacts::select_active, detect_proximity, detect_impacts), one
// invocation per kept candidate, in their order (self_select.comp: the particle-triangle pairs,
// then the edge pairs). Active: the two elements' boxes over the motion, grown by half the thickness, overlap
// (the others can neither come within the thickness nor touch). Of an active pair: its distance at
// the motion's start; near, within the thickness at the start or the end and apart at the start;
// touching, its first touch along the motion (collision/self_pair.inc).
#include "gpu/shaders/shared_text.glsl"
#include "core/closest_points.inc"
#include "collision/self_pair.inc"
#include "gpu/shaders/self_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Start { Real start[]; };  // [particles][3]
layout(std430, binding = 1) readonly buffer End { Real end[]; };
layout(std430, binding = 2) readonly buffer Triangles { uint triangles[]; };  // [triangles][3]
layout(std430, binding = 3) readonly buffer Edges { uint edges[]; };          // [edges][2]
layout(std430, binding = 4) readonly buffer PointBoxes { Real point_boxes[]; };  // grown by half the thickness
layout(std430, binding = 5) readonly buffer TriangleBoxes { Real triangle_boxes[]; };
layout(std430, binding = 6) readonly buffer EdgeBoxes { Real edge_boxes[]; };
layout(std430, binding = 7) readonly buffer Pairs { uint pairs[]; };  // [candidates][2] (self_step.h, kEdgePairBit)
layout(std430, binding = 8) writeonly buffer Flags { uint flags[]; };  // [candidates]: kPair* bits
layout(std430, binding = 9) writeonly buffer StartDistance { Real start_distance[]; };  // [candidates], m

// [0]: the thickness, m (in a buffer of Reals: a push constant would need a double's layout).
layout(std430, binding = 10) readonly buffer SelfReal { Real self_real[]; };

layout(push_constant) uniform Constants { DetectPassConstants constants; };

Vec3 box_low(uint kind, uint b) {
  const uint i = 6u * b;
  if (kind == 0u) return Vec3(point_boxes[i], point_boxes[i + 1u], point_boxes[i + 2u]);
  if (kind == 1u) return Vec3(triangle_boxes[i], triangle_boxes[i + 1u], triangle_boxes[i + 2u]);
  return Vec3(edge_boxes[i], edge_boxes[i + 1u], edge_boxes[i + 2u]);
}
Vec3 box_high(uint kind, uint b) {
  const uint i = 6u * b + 3u;
  if (kind == 0u) return Vec3(point_boxes[i], point_boxes[i + 1u], point_boxes[i + 2u]);
  if (kind == 1u) return Vec3(triangle_boxes[i], triangle_boxes[i + 1u], triangle_boxes[i + 2u]);
  return Vec3(edge_boxes[i], edge_boxes[i + 1u], edge_boxes[i + 2u]);
}
bool boxes_overlap(uint kind_a, uint a, uint kind_b, uint b) {
  return all(lessThanEqual(box_low(kind_a, a), box_high(kind_b, b))) &&
         all(lessThanEqual(box_low(kind_b, b), box_high(kind_a, a)));
}

PairCorners corners_of(uint particles[4], bool at_end) {
  PairCorners corners;
  for (uint k = 0u; k < 4u; ++k) {
    const uint p = particles[k];
    corners.x[k] = at_end ? Vec3(end[3u * p], end[3u * p + 1u], end[3u * p + 2u])
                          : Vec3(start[3u * p], start[3u * p + 1u], start[3u * p + 2u]);
  }
  return corners;
}

void main() {
  const uint c = invocation_index();
  if (c >= constants.candidates) return;
  const bool point = (pairs[2u * c] & kEdgePairBit) == 0u;
  uint particles[4];
  bool selected;
  if (point) {
    const uint p = pairs[2u * c];
    const uint t = pairs[2u * c + 1u];
    particles = uint[4](p, triangles[3u * t], triangles[3u * t + 1u], triangles[3u * t + 2u]);
    selected = boxes_overlap(0u, p, 1u, t);
  } else {
    const uint e = pairs[2u * c] & ~kEdgePairBit;
    const uint f = pairs[2u * c + 1u];
    particles = uint[4](edges[2u * e], edges[2u * e + 1u], edges[2u * f], edges[2u * f + 1u]);
    selected = boxes_overlap(2u, e, 2u, f);
  }
  uint flag = 0u;
  Real distance = Real(0.0);
  if (selected) {
    const int kind = point ? kPairPointTriangle : kPairEdgeEdge;
    const Real thickness = self_real[0];
    const PairCorners at_start = corners_of(particles, false);
    const PairCorners at_end = corners_of(particles, true);
    distance = measure_pair_corners(kind, at_start).distance;
    const bool within = distance < thickness || measure_pair_corners(kind, at_end).distance < thickness;
    flag = kPairActive | (within && distance != Real(0.0) ? kPairNear : 0u) |
           (first_touch(kind, at_start, at_end, thickness, distance) >= Real(0.0) ? kPairTouching : 0u);
  }
  flags[c] = flag;
  start_distance[c] = distance;
}
