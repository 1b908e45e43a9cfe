#version 450
#extension GL_GOOGLE_include_directive : require
// Self-collision's boxes of a motion on the device (gpu/device_self_candidates.h), as the CPU's
// SelfContacts::motion_boxes makes them: each particle's box over its motion start -> end, each
// triangle's and edge's the union of its particles' boxes grown by the margin, then the particles'
// boxes grown; and each grid's cell size, BoxGrid's mean extent of its boxes, summed in box order
// by one invocation (the same additions in the same order as the CPU's, so the same cells).
#include "gpu/shaders/shared_text.glsl"
#include "gpu/shaders/self_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Start { Real start[]; };  // [particles][3]
layout(std430, binding = 1) readonly buffer End { Real end[]; };
layout(std430, binding = 2) readonly buffer Triangles { uint triangles[]; };  // [triangles][3]
layout(std430, binding = 3) readonly buffer Edges { uint edges[]; };          // [edges][2]
layout(std430, binding = 4) buffer PointBoxes { Real point_boxes[]; };        // [particles][6]: low, high
layout(std430, binding = 5) buffer TriangleBoxes { Real triangle_boxes[]; };
layout(std430, binding = 6) buffer EdgeBoxes { Real edge_boxes[]; };
// [0] the margin, m; [1] and [2] the triangles' and the edges' mean extent, the grids' cell sizes.
layout(std430, binding = 7) buffer SelfReal { Real self_real[]; };

layout(push_constant) uniform Constants { BoxesPassConstants constants; };

Vec3 at(uint p, bool at_end) {
  return at_end ? Vec3(end[3u * p], end[3u * p + 1u], end[3u * p + 2u])
                : Vec3(start[3u * p], start[3u * p + 1u], start[3u * p + 2u]);
}
Vec3 point_low(uint p) { return Vec3(point_boxes[6u * p], point_boxes[6u * p + 1u], point_boxes[6u * p + 2u]); }
Vec3 point_high(uint p) { return Vec3(point_boxes[6u * p + 3u], point_boxes[6u * p + 4u], point_boxes[6u * p + 5u]); }

void store_box(uint k, Vec3 low, Vec3 high) {
  const bool triangle = k < constants.triangles;
  const uint i = 6u * (triangle ? k : k - constants.triangles);
  for (uint a = 0u; a < 3u; ++a) {
    if (triangle) {
      triangle_boxes[i + a] = low[a];
      triangle_boxes[i + 3u + a] = high[a];
    } else {
      edge_boxes[i + a] = low[a];
      edge_boxes[i + 3u + a] = high[a];
    }
  }
}

// The mean of the boxes' largest extents, or 1 m for none or only point-sized ones (BoxGrid::build).
Real cell_size(bool triangles_grid) {
  const uint count = triangles_grid ? constants.triangles : constants.edges;
  Real sum = Real(0.0);
  for (uint b = 0u; b < count; ++b) {
    const uint i = 6u * b;
    const Vec3 span = triangles_grid ? Vec3(triangle_boxes[i + 3u] - triangle_boxes[i],
                                            triangle_boxes[i + 4u] - triangle_boxes[i + 1u],
                                            triangle_boxes[i + 5u] - triangle_boxes[i + 2u])
                                     : Vec3(edge_boxes[i + 3u] - edge_boxes[i], edge_boxes[i + 4u] - edge_boxes[i + 1u],
                                            edge_boxes[i + 5u] - edge_boxes[i + 2u]);
    sum += max(max(span.x, span.y), span.z);
  }
  const Real mean = count == 0u ? Real(0.0) : sum / Real(count);
  return mean > Real(0.0) ? mean : Real(1.0);
}

void main() {
  const uint k = invocation_index();
  const Real margin = self_real[0];
  if (constants.phase == kBoxesPoints) {
    if (k >= constants.particles) return;
    const Vec3 a = at(k, false);
    const Vec3 b = at(k, true);
    const Vec3 low = min(a, b);
    const Vec3 high = max(a, b);
    for (uint i = 0u; i < 3u; ++i) {
      point_boxes[6u * k + i] = low[i];
      point_boxes[6u * k + 3u + i] = high[i];
    }
  } else if (constants.phase == kBoxesElements) {
    if (k >= constants.triangles + constants.edges) return;
    const bool triangle = k < constants.triangles;
    const uint corners = triangle ? 3u : 2u;
    const uint first = triangle ? 3u * k : 2u * (k - constants.triangles);
    uint p = triangle ? triangles[first] : edges[first];
    Vec3 low = point_low(p);
    Vec3 high = point_high(p);
    for (uint c = 1u; c < corners; ++c) {
      p = triangle ? triangles[first + c] : edges[first + c];
      low = min(low, point_low(p));
      high = max(high, point_high(p));
    }
    store_box(k, low - Vec3(margin), high + Vec3(margin));
  } else if (constants.phase == kBoxesGrow) {
    if (k >= constants.particles) return;
    for (uint i = 0u; i < 3u; ++i) {
      point_boxes[6u * k + i] -= margin;
      point_boxes[6u * k + 3u + i] += margin;
    }
  } else if (k == 0u) {
    self_real[1] = cell_size(true);
    self_real[2] = cell_size(false);
  }
}
