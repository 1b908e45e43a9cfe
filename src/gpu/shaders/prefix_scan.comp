#version 450
#extension GL_GOOGLE_include_directive : require
// An exclusive prefix sum of unsigned counts on the device (gpu/prefix_scan.h): values[i] becomes
// the sum of values[0 .. i), and the total is written after the blocks' sums. Three passes:
//   kScanBlocks     each workgroup scans its kScanWorkgroup values in shared memory and writes
//                   their total to block_sums[workgroup]
//   kScanBlockSums  one workgroup scans the blocks' totals in chunks of kScanWorkgroup, carrying
//                   the running sum, and writes the whole total to block_sums[blocks]
//   kScanAdd        each value takes its block's offset
// Integer sums: the same result in any order, so the same on every run.
#include "gpu/shaders/prefix_scan.h"

const uint kWorkgroupSize = kScanWorkgroup;
layout(local_size_x = kScanWorkgroup) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) buffer Values { uint values[]; };         // [count]
layout(std430, binding = 1) buffer BlockSums { uint block_sums[]; };  // [blocks + 1]

layout(push_constant) uniform Constants { ScanPassConstants constants; };

shared uint scanned[kScanWorkgroup];

// The inclusive sum over the workgroup of each invocation's `value`, up to and with its own
// (Hillis and Steele's scan: log2 of the workgroup's steps).
uint inclusive_scan(uint value) {
  const uint i = gl_LocalInvocationID.x;
  barrier();  // `scanned` is free: a scan before this one has been read
  scanned[i] = value;
  barrier();
  for (uint offset = 1u; offset < kScanWorkgroup; offset *= 2u) {
    const uint before = i >= offset ? scanned[i - offset] : 0u;
    barrier();
    scanned[i] += before;
    barrier();
  }
  return scanned[i];
}

void main() {
  const uint i = gl_LocalInvocationID.x;
  if (constants.phase == kScanBlocks) {
    const uint k = invocation_index();
    const uint value = k < constants.count ? values[k] : 0u;
    const uint inclusive = inclusive_scan(value);
    if (k < constants.count) values[k] = inclusive - value;
    if (i == kScanWorkgroup - 1u) block_sums[workgroup_index()] = inclusive;
  } else if (constants.phase == kScanBlockSums) {
    uint running = 0u;
    for (uint first = 0u; first < constants.blocks; first += kScanWorkgroup) {
      const uint b = first + i;
      const uint value = b < constants.blocks ? block_sums[b] : 0u;
      const uint inclusive = inclusive_scan(value);
      if (b < constants.blocks) block_sums[b] = running + inclusive - value;
      running += scanned[kScanWorkgroup - 1u];
    }
    if (i == 0u) block_sums[constants.blocks] = running;
  } else {
    const uint k = invocation_index();
    if (k < constants.count) values[k] += block_sums[workgroup_index()];
  }
}
