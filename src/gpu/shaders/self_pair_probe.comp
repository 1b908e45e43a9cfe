#version 450
#extension GL_GOOGLE_include_directive : require
// Self-collision's pair geometry as the shaders compile it (collision/self_pair.inc), one pair per
// invocation, for tests/gpu's test_self_pair.cpp, which holds it to the CPU's compilation of the
// same text and to a brute-force oracle: the distance, normal and weights at the motion's start,
// the bound on the distance's rate, the first touch along the motion, the distance at its end.
// No pass of the backend uses it yet: it is the first part of self-collision on the device.
#include "gpu/shaders/shared_text.glsl"
#include "core/closest_points.inc"
#include "collision/self_pair.inc"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

// A case: the kind, the thickness, then the 4 corners at the motion's start and at its end.
const uint kInputs = 26u;
// Its results: the distance, the normal (3) and the weights (4) at the start, the rate's bound, the
// first touch (-1: none) and the distance at the end.
const uint kOutputs = 11u;

layout(std430, binding = 0) readonly buffer Inputs { Real inputs[]; };     // [cases][kInputs]
layout(std430, binding = 1) writeonly buffer Outputs { Real outputs[]; };  // [cases][kOutputs]

layout(push_constant) uniform Constants { uint count; } constants;

PairCorners corners_at(uint first) {
  PairCorners corners;
  for (uint k = 0u; k < 4u; ++k) {
    const uint i = first + 3u * k;
    corners.x[k] = Vec3(inputs[i], inputs[i + 1u], inputs[i + 2u]);
  }
  return corners;
}

void main() {
  const uint c = invocation_index();
  if (c >= constants.count) return;
  const uint in_base = kInputs * c;
  const int kind = int(inputs[in_base]);
  const Real thickness = inputs[in_base + 1u];
  const PairCorners start = corners_at(in_base + 2u);
  const PairCorners end = corners_at(in_base + 14u);
  const PairMeasure measure = measure_pair_corners(kind, start);
  const uint out_base = kOutputs * c;
  outputs[out_base] = measure.distance;
  for (uint k = 0u; k < 3u; ++k) outputs[out_base + 1u + k] = measure.normal[k];
  for (uint k = 0u; k < 4u; ++k) outputs[out_base + 4u + k] = measure.weight[k];
  outputs[out_base + 8u] = pair_motion_bound(kind, start, end);
  outputs[out_base + 9u] = first_touch(kind, start, end, thickness, measure.distance);
  outputs[out_base + 10u] = measure_pair_corners(kind, end).distance;
}
