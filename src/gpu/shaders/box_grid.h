// The layout shared by the device's box grid (gpu/device_box_grid.h) and its shader box_grid.comp:
// the phases, the entry's words and the push constants, read by C++ and by GLSL.
#if defined(__cplusplus)
#pragma once
#include <cstdint>
namespace clothsim::gpu {
using uint = std::uint32_t;
#define CLOTHSIM_SLOT inline constexpr uint
#else
#define CLOTHSIM_SLOT const uint
#endif

CLOTHSIM_SLOT kGridCells = 0;     // per box: its lowest cell, how many it enters (0: kept aside), the extent
CLOTHSIM_SLOT kGridOversize = 1;  // per box kept aside: its place in the list of them
CLOTHSIM_SLOT kGridEntries = 2;   // per entered box: its entries, in cell order, and its buckets' counts
CLOTHSIM_SLOT kGridFill = 3;      // per entry: the next free place of its bucket
CLOTHSIM_SLOT kGridSort = 4;      // per bucket: its entries by entry index (box, then cell)
// A box more than this many cells across on some axis is kept aside (BoxGrid::kOversize).
CLOTHSIM_SLOT kOversizeCells = 8;

// An entry's words: its cell (three ints), its box, and which of the box's lowest cells it is on
// (bit a along axis a).
CLOTHSIM_SLOT kEntryWords = 5;
CLOTHSIM_SLOT kEntryBox = 3;
CLOTHSIM_SLOT kEntryLowest = 4;

struct GridPassConstants {
  uint phase;        // kGrid*
  uint boxes;        // how many
  uint bucket_mask;  // buckets - 1, a power of two less one
  uint entries;      // how many (kGridFill, kGridSort)
};

// box_grid_query.comp's phases and push constants.
CLOTHSIM_SLOT kQueryCount = 0;  // per query: how many stored boxes it finds
CLOTHSIM_SLOT kQueryWrite = 1;  // per query: its pairs, from its scanned offset
CLOTHSIM_SLOT kJoinCount = 2;   // per bucket, then per box kept aside: how many pairs of stored boxes it finds
CLOTHSIM_SLOT kJoinWrite = 3;   // the same, writing them from its scanned offset

struct GridQueryConstants {
  uint phase;            // kQuery*
  uint queries;          // how many
  uint bucket_mask;      // the grid's
  uint entries;          // the grid's entries
  uint oversize;         // the grid's boxes kept aside
  uint exclude_corners;  // queries: 1 skips a stored box whose 3 exclude words name the query; the
                         // join: 1 skips two boxes whose 2 exclude words share one (two edges' particles)
  uint stored;           // the grid's boxes
};

#if defined(__cplusplus)
#undef CLOTHSIM_SLOT
}  // namespace clothsim::gpu
#endif
