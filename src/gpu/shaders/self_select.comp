#version 450
#extension GL_GOOGLE_include_directive : require
// Which of the search's pairs self-collision keeps (gpu/device_self_candidates.h), as the CPU's
// SelfContacts::prune_blocks keeps them: every pair, or those nearer than the reach at the
// positions given; the kept ones then written in the search's order (the particle-triangle pairs,
// then the edge pairs) as two words each (self_step.h, kEdgePairBit), at the exclusive sum of the
// keep flags before them.
#include "gpu/shaders/shared_text.glsl"
#include "core/closest_points.inc"
#include "collision/self_pair.inc"
#include "gpu/shaders/self_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Position { Real x[]; };            // [particles][3]
layout(std430, binding = 1) readonly buffer Triangles { uint triangles[]; };    // [triangles][3]
layout(std430, binding = 2) readonly buffer Edges { uint edges[]; };            // [edges][2]
layout(std430, binding = 3) readonly buffer PointPairs { uint point_pairs[]; };  // [pairs][2]: particle, triangle
layout(std430, binding = 4) readonly buffer EdgePairs { uint edge_pairs[]; };    // [pairs][2]: edge, edge
layout(std430, binding = 5) buffer Keep { uint keep[]; };           // [search's pairs]: 1 kept, then scanned
layout(std430, binding = 6) buffer KeepFlag { uint keep_flag[]; };  // [search's pairs]: 1 kept
layout(std430, binding = 7) writeonly buffer Pairs { uint pairs[]; };  // [kept][2]
// [0]: the reach, m (in a buffer of Reals: a push constant would need a double's layout).
layout(std430, binding = 8) readonly buffer SelectReal { Real select_real[]; };

layout(push_constant) uniform Constants { SelectPassConstants constants; };

Vec3 at(uint p) { return Vec3(x[3u * p], x[3u * p + 1u], x[3u * p + 2u]); }

void main() {
  const uint c = invocation_index();
  if (c >= constants.point_pairs + constants.edge_pairs) return;
  const bool point = c < constants.point_pairs;
  const uint first = point ? point_pairs[2u * c] : edge_pairs[2u * (c - constants.point_pairs)] | kEdgePairBit;
  const uint second = point ? point_pairs[2u * c + 1u] : edge_pairs[2u * (c - constants.point_pairs) + 1u];
  if (constants.phase == kSelectMeasure) {
    bool kept = constants.keep_all != 0u;
    if (!kept) {
      PairCorners corners;
      if (point) {
        corners.x[0] = at(first);
        for (uint k = 0u; k < 3u; ++k) corners.x[k + 1u] = at(triangles[3u * second + k]);
      } else {
        const uint e = first & ~kEdgePairBit;
        corners.x[0] = at(edges[2u * e]);
        corners.x[1] = at(edges[2u * e + 1u]);
        corners.x[2] = at(edges[2u * second]);
        corners.x[3] = at(edges[2u * second + 1u]);
      }
      kept = measure_pair_corners(point ? kPairPointTriangle : kPairEdgeEdge, corners).distance < select_real[0];
    }
    keep[c] = kept ? 1u : 0u;
    keep_flag[c] = kept ? 1u : 0u;
  } else if (keep_flag[c] != 0u) {
    pairs[2u * keep[c]] = first;
    pairs[2u * keep[c] + 1u] = second;
  }
}
