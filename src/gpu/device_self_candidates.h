// Self-collision's candidates on the device (docs/gpu.md, "Not done yet"): stage 1 of the CPU's
// self pass (collision/self_contacts.h, SelfContacts::find_candidates) with the same boxes, grids
// and order, so the same pairs in the same order. From the positions at a motion's start and end:
//   self_boxes       each particle's, triangle's and edge's box over the motion, grown by the margin,
//                    and each grid's cell size (the mean extent, summed as the CPU sums it)
//   box_grid         the triangles' grid and the edges' (gpu/device_box_grid.h)
//   box_grid_query   each particle against the triangles' grid, its own triangles skipped; then
//                    the edges' grid joined with itself, two edges with a particle in common skipped
//   self_select      the pairs kept (all, or those nearer than a reach at given positions), in
//                    their order, as two words each (shaders/self_step.h)
// The point-triangle pairs come first, by particle, then the edge pairs, by bucket, as on the CPU.
// Each build reads back a few words between its submissions (the cell sizes, the counts that size
// the arrays). The self pass on the device (gpu/device_self_contacts.h) uses it.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "collision/sheet_elements.h"
#include "core/precision.h"
#include "gpu/buffer.h"
#include "gpu/compute_pipeline.h"
#include "gpu/device.h"
#include "gpu/device_box_grid.h"
#include "gpu/prefix_scan.h"

namespace clothsim::gpu {

class DeviceSelfCandidates {
 public:
  // For a sheet of `particles` particles whose self-collision elements are `elements`.
  DeviceSelfCandidates(Device& device, Precision precision, std::uint32_t particles, const SheetElements& elements);

  // Takes the sheet's elements as they are now (a torn sheet's), keeping the passes and the grids:
  // false, changing nothing, where there are more of either kind than it was made for. The next
  // find() finds the candidates anew.
  bool set_elements(const SheetElements& elements);

  // The candidates of the motion `start` -> `end` ([particles][3] Reals each) with boxes grown by
  // `margin` m, all kept.
  void find(const Buffer& start, const Buffer& end, double margin);
  // Keeps of the last find()'s candidates those nearer than `reach` m at positions `x`, in order
  // (SelfContacts::prune_blocks).
  void prune(const Buffer& x, double reach);

  // Stages 2 and 3's tests of the last find()'s candidates over the motion `start` -> `end`, as the
  // CPU's self pass makes them (self_detect.comp): which are active (their boxes, grown by half
  // the `thickness`, overlap), and of those the distance at the start, which are near and which
  // touch.
  void detect(const Buffer& start, const Buffer& end, double thickness);
  // The same in two parts, to record into a submission of the caller's: its arrays sized and its
  // passes bound (outside the submission), then its passes recorded.
  void prepare_detect(const Buffer& start, const Buffer& end, double thickness);
  void record_detect(VkCommandBuffer commands) const;
  // Read back (tests), per candidate: its kPair* bits (shaders/self_step.h), and the distance at the
  // start (0 where not active).
  std::vector<std::uint32_t> flags() const;
  const Buffer& flag_buffer() const { return flags_; }
  std::vector<double> start_distances() const;

  // The candidates kept: [candidate_count()][2] words (shaders/self_step.h, kEdgePairBit).
  std::uint32_t candidate_count() const { return kept_count_; }
  const Buffer& pair_buffer() const { return pairs_; }
  std::vector<std::uint32_t> pairs() const;  // read back (tests)
  const Buffer& triangle_buffer() const { return triangle_corners_; }
  const Buffer& edge_buffer() const { return edge_ends_; }

  std::uint32_t point_triangle_count() const { return point_triangle_count_; }
  std::uint32_t edge_pair_count() const { return edge_pair_count_; }
  // Read back (tests): (particle, triangle) pairs, then (edge, edge) pairs, [pairs][2] each.
  std::vector<std::uint32_t> point_triangle_pairs() const { return point_query_.pairs(); }
  std::vector<std::uint32_t> edge_pairs() const { return edge_query_.pairs(); }

 private:
  Device& device_;
  Precision precision_;
  std::uint32_t particles_, triangles_, edges_;
  std::uint32_t triangle_capacity_, edge_capacity_;  // the elements made for: the boxes' and grids' room
  std::uint32_t point_triangle_count_ = 0;
  std::uint32_t edge_pair_count_ = 0;
  std::uint32_t kept_count_ = 0;
  double margin_ = -1.0;            // m: the margin self_real_ holds (none yet)
  double detect_thickness_ = -1.0;  // m: the thickness detect_real_ holds
  // The motion's boxes grown by `margin`: bound, then recorded, with `cell_sizes` the grids' cell
  // sizes into self_real_ (one invocation's sum over every box: only where a grid is built).
  void bind_boxes(const Buffer& start, const Buffer& end, double margin);
  void record_boxes(VkCommandBuffer commands, bool cell_sizes) const;
  // The search's pairs kept into pairs_: all (no `x`), or those nearer than `reach` at `x`.
  void select(const Buffer* x, double reach);

  Buffer triangle_corners_, edge_ends_, point_boxes_, triangle_boxes_, edge_boxes_, self_real_, detect_real_, flags_,
      start_distance_, keep_, keep_flag_, pairs_, select_real_;
  ComputePipeline boxes_pass_, select_pass_, detect_pass_;
  PrefixScan keep_scan_;
  DeviceBoxGrid triangle_grid_, edge_grid_;
  DeviceGridQuery point_query_, edge_query_;
};

}  // namespace clothsim::gpu
