// The hashed grid's boxes, cells and buckets (collision/box_grid.h's BoxGrid::cell_of and bucket_of
// on the device), for box_grid.comp, which builds the grid, and box_grid_query.comp, which queries
// it. The includer includes the shared text's spelling and box_grid.h first, and declares the
// grid's stored boxes, boxes ([boxes][6] Reals: low, high), and grid_real ([0]: the cell size).
#ifndef CLOTHSIM_BOX_GRID_GLSL
#define CLOTHSIM_BOX_GRID_GLSL

const Real kOversize = Real(kOversizeCells);
// Cells beyond this are clamped (BoxGrid's 64-bit cells clamp at 1e15; 2^30 cells of any size a
// sheet has are far past its positions).
const Real kFarCell = Real(1073741824.0);

ivec3 cell_of(Vec3 x, Real cell_size) {
  return ivec3(clamp(floor(x / cell_size), Vec3(-kFarCell), Vec3(kFarCell)));
}

// Teschner et al.'s hash (BoxGrid::bucket_of): the low 32 bits of the 64-bit products are those of
// the 32-bit ones, and the mask keeps fewer.
uint bucket_of(ivec3 cell, uint bucket_mask) {
  return ((uint(cell.x) * 73856093u) ^ (uint(cell.y) * 19349663u) ^ (uint(cell.z) * 83492791u)) & bucket_mask;
}

Vec3 box_low(uint b) { return Vec3(boxes[6u * b], boxes[6u * b + 1u], boxes[6u * b + 2u]); }
Vec3 box_high(uint b) { return Vec3(boxes[6u * b + 3u], boxes[6u * b + 4u], boxes[6u * b + 5u]); }

// Whether stored box b is more than kOversize cells across on an axis (BoxGrid keeps it aside).
bool kept_aside(uint b) {
  const Vec3 span = box_high(b) - box_low(b);
  return max(span.x, max(span.y, span.z)) > kOversize * grid_real[0];
}

#endif
