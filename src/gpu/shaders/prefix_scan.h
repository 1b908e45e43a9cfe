// The layout shared by the device's prefix sum (gpu/prefix_scan.h) and its shader prefix_scan.comp:
// the phases, the workgroup and the push constants, read by C++ and by GLSL.
#if defined(__cplusplus)
#pragma once
#include <cstdint>
namespace clothsim::gpu {
using uint = std::uint32_t;
#define CLOTHSIM_SLOT inline constexpr uint
#else
#define CLOTHSIM_SLOT const uint
#endif

CLOTHSIM_SLOT kScanBlocks = 0;     // each workgroup's values scanned, their total into block_sums
CLOTHSIM_SLOT kScanBlockSums = 1;  // the blocks' totals scanned by one workgroup, the whole total after them
CLOTHSIM_SLOT kScanAdd = 2;        // each value plus its block's offset
// Values per block: the workgroup of every phase.
CLOTHSIM_SLOT kScanWorkgroup = 256;

struct ScanPassConstants {
  uint phase;   // kScan*
  uint count;   // values
  uint blocks;  // ceil(count / kScanWorkgroup)
};

#if defined(__cplusplus)
#undef CLOTHSIM_SLOT
}  // namespace clothsim::gpu
#endif
