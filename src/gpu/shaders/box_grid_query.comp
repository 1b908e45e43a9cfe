#version 450
#extension GL_GOOGLE_include_directive : require
// The hashed grid's queries on the device (gpu/device_box_grid.h, DeviceGridQuery), as the CPU's
// BoxGrid visits them. Queries (for_each_overlap): one invocation per query box, over the cells
// its box overlaps within the entered boxes' extent, each bucket's entries of that cell whose box
// overlaps the query, reported only in the cell of the two boxes' intersection's lowest corner (so
// once), then the boxes kept aside; a stored box whose `exclude` words name the query is skipped
// (a triangle of which the particle is a corner). The join (for_each_pair): one invocation per
// bucket, each pair of its entries of one cell whose boxes overlap, reported in the lowest corner's
// cell, then one per box kept aside, paired with every other box; two boxes whose `exclude` words
// share one are skipped (two edges with a particle in common). Two passes each: every invocation
// counts what it finds, the counts are scanned (prefix_scan.comp), and each writes its pairs from
// its offset, in the CPU's order.
#include "gpu/shaders/shared_text.glsl"
#include "gpu/shaders/box_grid.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Queries { Real queries[]; };  // [queries][6]: low, high
layout(std430, binding = 1) readonly buffer Boxes { Real boxes[]; };      // the grid's stored boxes
layout(std430, binding = 2) readonly buffer GridReal { Real grid_real[]; };
layout(std430, binding = 3) readonly buffer Extent { int extent[]; };
layout(std430, binding = 4) readonly buffer Entries { uint entries[]; };
layout(std430, binding = 5) readonly buffer BucketStart { uint bucket_start[]; };
layout(std430, binding = 6) readonly buffer Sorted { uint sorted[]; };
layout(std430, binding = 7) readonly buffer Oversize { uint oversize[]; };
layout(std430, binding = 8) readonly buffer Exclude { uint exclude[]; };  // [stored][3], with `exclude_corners`
layout(std430, binding = 9) buffer Counts { uint counts[]; };             // [queries]: found; then, scanned, offsets
layout(std430, binding = 10) writeonly buffer Pairs { uint pairs[]; };   // [pairs][2]: query, stored box

layout(push_constant) uniform Constants { GridQueryConstants constants; };

#include "gpu/shaders/box_grid.glsl"

Vec3 query_low(uint q) { return Vec3(queries[6u * q], queries[6u * q + 1u], queries[6u * q + 2u]); }
Vec3 query_high(uint q) { return Vec3(queries[6u * q + 3u], queries[6u * q + 4u], queries[6u * q + 5u]); }

bool overlaps(uint b, Vec3 low, Vec3 high) {
  return all(lessThanEqual(box_low(b), high)) && all(lessThanEqual(low, box_high(b)));
}

bool excluded(uint b, uint q) {
  if (constants.exclude_corners == 0u) return false;
  return exclude[3u * b] == q || exclude[3u * b + 1u] == q || exclude[3u * b + 2u] == q;
}

bool share(uint a, uint b) {
  if (constants.exclude_corners == 0u) return false;
  return exclude[2u * a] == exclude[2u * b] || exclude[2u * a] == exclude[2u * b + 1u] ||
         exclude[2u * a + 1u] == exclude[2u * b] || exclude[2u * a + 1u] == exclude[2u * b + 1u];
}

bool overlaps_box(uint a, uint b) { return overlaps(a, box_low(b), box_high(b)); }

// Invocation k of the join: bucket k, or past the buckets the k-th box kept aside.
void join(uint k, bool write) {
  const uint first = write ? counts[k] : 0u;
  uint found = 0u;
  const uint buckets = constants.bucket_mask + 1u;
  if (k < buckets) {
    const uint end = k == constants.bucket_mask ? constants.entries : bucket_start[k + 1u];
    for (uint s = bucket_start[k]; s < end; ++s) {
      const uint a = kEntryWords * sorted[s];
      for (uint t = s + 1u; t < end; ++t) {
        const uint b = kEntryWords * sorted[t];
        if (entries[a] != entries[b] || entries[a + 1u] != entries[b + 1u] || entries[a + 2u] != entries[b + 2u]) {
          continue;
        }
        const uint box_a = entries[a + kEntryBox];
        const uint box_b = entries[b + kEntryBox];
        if ((entries[a + kEntryLowest] | entries[b + kEntryLowest]) != 7u || !overlaps_box(box_a, box_b) ||
            share(box_a, box_b)) {
          continue;
        }
        if (write) {
          pairs[2u * (first + found)] = box_a;  // box_a < box_b: a bucket's entries are in box order
          pairs[2u * (first + found) + 1u] = box_b;
        }
        ++found;
      }
    }
  } else {
    const uint big = oversize[k - buckets];
    for (uint j = 0u; j < constants.stored; ++j) {
      // Two boxes kept aside are paired once, when the smaller is `big`.
      if (j == big || (j < big && kept_aside(j)) || !overlaps_box(big, j) || share(big, j)) continue;
      if (write) {
        pairs[2u * (first + found)] = min(big, j);
        pairs[2u * (first + found) + 1u] = max(big, j);
      }
      ++found;
    }
  }
  if (!write) counts[k] = found;
}

void main() {
  const uint q = invocation_index();
  if (constants.phase == kJoinCount || constants.phase == kJoinWrite) {
    if (q < constants.bucket_mask + 1u + constants.oversize) join(q, constants.phase == kJoinWrite);
    return;
  }
  if (q >= constants.queries) return;
  const bool write = constants.phase == kQueryWrite;
  const uint first = write ? counts[q] : 0u;
  uint found = 0u;
  const Vec3 low_corner = query_low(q);
  const Vec3 high_corner = query_high(q);
  const Real size = grid_real[0];
  const ivec3 low = cell_of(low_corner, size);
  const ivec3 high = min(cell_of(high_corner, size), ivec3(extent[3], extent[4], extent[5]));
  const ivec3 start = max(low, ivec3(extent[0], extent[1], extent[2]));
  for (int x = start.x; x <= high.x; ++x) {
    for (int y = start.y; y <= high.y; ++y) {
      for (int z = start.z; z <= high.z; ++z) {
        const uint bucket = bucket_of(ivec3(x, y, z), constants.bucket_mask);
        const uint end = bucket == constants.bucket_mask ? constants.entries : bucket_start[bucket + 1u];
        for (uint s = bucket_start[bucket]; s < end; ++s) {
          const uint e = kEntryWords * sorted[s];
          if (int(entries[e]) != x || int(entries[e + 1u]) != y || int(entries[e + 2u]) != z) continue;
          const uint lowest = entries[e + kEntryLowest] | (low.x == x ? 1u : 0u) | (low.y == y ? 2u : 0u) |
                              (low.z == z ? 4u : 0u);
          const uint b = entries[e + kEntryBox];
          if (lowest != 7u || !overlaps(b, low_corner, high_corner) || excluded(b, q)) continue;
          if (write) {
            pairs[2u * (first + found)] = q;
            pairs[2u * (first + found) + 1u] = b;
          }
          ++found;
        }
      }
    }
  }
  for (uint o = 0u; o < constants.oversize; ++o) {
    const uint b = oversize[o];
    if (!overlaps(b, low_corner, high_corner) || excluded(b, q)) continue;
    if (write) {
      pairs[2u * (first + found)] = q;
      pairs[2u * (first + found) + 1u] = b;
    }
    ++found;
  }
  if (!write) counts[q] = found;
}
