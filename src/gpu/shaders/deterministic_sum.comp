#version 450
#extension GL_GOOGLE_include_directive : require
// deterministic_sum (src/forces/forces.cpp) on the device: the sum of `values` over fixed blocks
// of block_size items (forces.cpp's kReductionBlock), each summed in index order, and the block sums added in block order,
// the same additions in the same order as the CPU, so the result does not depend on how the
// invocations are scheduled. Two dispatches: phase 0, one invocation per block; phase 1, one
// invocation adds the blocks. Slower than a tree reduction, and reproducible.
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/element_pass.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Values { Real values[]; };  // [count]
layout(std430, binding = 1) buffer BlockSums { Real block_sums[]; };    // [ceil(count / block_size)]
layout(std430, binding = 2) writeonly buffer Sum { Real sum[]; };       // [1]

layout(push_constant) uniform Constants { SumConstants constants; };

void main() {
  const uint index = invocation_index();
  const uint blocks = (constants.count + constants.block_size - 1) / constants.block_size;
  if (constants.phase == 0u) {
    if (index >= blocks) return;
    const uint begin = index * constants.block_size;
    const uint end = min(constants.count, begin + constants.block_size);
    Real total = Real(0.0);
    for (uint i = begin; i < end; ++i) total += values[i];
    block_sums[index] = total;
  } else {
    if (index != 0u) return;
    Real total = Real(0.0);
    for (uint block = 0u; block < blocks; ++block) total += block_sums[block];
    sum[0] = total;
  }
}
