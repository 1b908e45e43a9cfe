#version 450
#extension GL_GOOGLE_include_directive : require
// The broad phase's hashed grid of boxes on the device (gpu/device_box_grid.h), built as the CPU's
// BoxGrid::build builds it (collision/box_grid.h), so that for the same cell size the buckets hold
// the same entries in the same order: each box enters every cell it overlaps, unless it is more
// than kOversize cells across on an axis (kept aside); a cell's bucket is Teschner et al.'s hash
// of its three coordinates; a bucket's entries are in box order, each box's cells in x, y, z order.
// Counted, scanned (prefix_scan.comp) and written, then sorted within each bucket: the result does
// not depend on the order of the atomic increments that fill the buckets.
#include "gpu/shaders/shared_text.glsl"
#include "gpu/shaders/box_grid.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Boxes { Real boxes[]; };  // [boxes][6]: low, high
layout(std430, binding = 1) readonly buffer GridReal { Real grid_real[]; };  // [0]: the cell size, m
layout(std430, binding = 2) buffer LowCell { int low_cell[]; };              // [boxes][3]
layout(std430, binding = 3) buffer CellsOf { uint cells_of[]; };  // [boxes]: entries; then, scanned, the first
layout(std430, binding = 4) buffer OversizeFlag { uint oversize_flag[]; };  // [boxes]: 1 kept aside; then scanned
layout(std430, binding = 5) writeonly buffer Oversize { uint oversize[]; };  // the boxes kept aside, ascending
layout(std430, binding = 6) buffer Extent { int extent[]; };  // low x, y, z, high x, y, z of the entered boxes
layout(std430, binding = 7) buffer Entries { uint entries[]; };           // [entries][kEntryWords]
layout(std430, binding = 8) buffer BucketStart { uint bucket_start[]; };  // [buckets]: counts; then scanned
layout(std430, binding = 9) buffer Fill { uint fill[]; };                 // [buckets], zero before kGridFill
layout(std430, binding = 10) buffer Sorted { uint sorted[]; };            // [entries]: entry indices by bucket

layout(push_constant) uniform Constants { GridPassConstants constants; };

#include "gpu/shaders/box_grid.glsl"

ivec3 entry_cell(uint e) {
  return ivec3(int(entries[kEntryWords * e]), int(entries[kEntryWords * e + 1u]), int(entries[kEntryWords * e + 2u]));
}

void main() {
  const uint k = invocation_index();
  if (constants.phase == kGridCells) {
    if (k >= constants.boxes) return;
    const ivec3 low = cell_of(box_low(k), grid_real[0]);
    for (uint axis = 0u; axis < 3u; ++axis) low_cell[3u * k + axis] = low[axis];
    const bool aside = kept_aside(k);
    oversize_flag[k] = aside ? 1u : 0u;
    if (aside) {
      cells_of[k] = 0u;
      return;
    }
    const ivec3 high = cell_of(box_high(k), grid_real[0]);
    const ivec3 span = high - low + ivec3(1);
    cells_of[k] = uint(span.x) * uint(span.y) * uint(span.z);
    for (uint axis = 0u; axis < 3u; ++axis) {
      atomicMin(extent[axis], low[axis]);
      atomicMax(extent[3u + axis], high[axis]);
    }
  } else if (constants.phase == kGridOversize) {
    if (k < constants.boxes && kept_aside(k)) oversize[oversize_flag[k]] = k;
  } else if (constants.phase == kGridEntries) {
    if (k >= constants.boxes || kept_aside(k)) return;
    const ivec3 low = ivec3(low_cell[3u * k], low_cell[3u * k + 1u], low_cell[3u * k + 2u]);
    const ivec3 high = cell_of(box_high(k), grid_real[0]);
    uint e = cells_of[k];
    for (int x = low.x; x <= high.x; ++x) {
      for (int y = low.y; y <= high.y; ++y) {
        for (int z = low.z; z <= high.z; ++z) {
          const uint lowest = (x == low.x ? 1u : 0u) | (y == low.y ? 2u : 0u) | (z == low.z ? 4u : 0u);
          entries[kEntryWords * e] = uint(x);
          entries[kEntryWords * e + 1u] = uint(y);
          entries[kEntryWords * e + 2u] = uint(z);
          entries[kEntryWords * e + kEntryBox] = k;
          entries[kEntryWords * e + kEntryLowest] = lowest;
          atomicAdd(bucket_start[bucket_of(ivec3(x, y, z), constants.bucket_mask)], 1u);
          ++e;
        }
      }
    }
  } else if (constants.phase == kGridFill) {
    if (k >= constants.entries) return;
    const uint b = bucket_of(entry_cell(k), constants.bucket_mask);
    sorted[bucket_start[b] + atomicAdd(fill[b], 1u)] = k;
  } else {
    // kGridSort: an insertion sort; a bucket holds a few entries (about twice as many buckets as entries).
    if (k > constants.bucket_mask) return;
    const uint first = bucket_start[k];
    const uint end = k == constants.bucket_mask ? constants.entries : bucket_start[k + 1u];
    for (uint i = first + 1u; i < end; ++i) {
      const uint value = sorted[i];
      uint j = i;
      while (j > first && sorted[j - 1u] > value) {
        sorted[j] = sorted[j - 1u];
        --j;
      }
      sorted[j] = value;
    }
  }
}
