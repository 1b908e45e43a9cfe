// Self-collision on the device: the CPU's self pass (collision/self_contacts.h) on state that stays
// on the device, driven by the host, which reads back a few words between its submissions (how far
// the sheet moved, how many pairs each stage lists). docs/gpu.md, "Self-collision on the device".
//
// After a step from positions x0 to the state (x1, v1):
//   1. candidates  found (gpu/device_self_candidates.h) with boxes over the step grown by the
//                  thickness and a reach, the CPU's pairs in its order, pruned as the CPU prunes
//                  them, and kept over the next steps while no particle moves further than the
//                  reach (the CPU's rule, SelfContacts::refresh_candidates)
//   2. proximity   the pairs within the thickness at x0 or x1 held on their side of x0, the
//                  thickness apart, with inelastic contact and Coulomb friction
//   3. impacts     the pairs whose motion touches (conservative advancement) have their closing
//                  motion removed, in rounds of detection and response
// Stages 2 and 3 respond as the CPU does to each pair, but all of a round's pairs at once, each
// particle taking its pairs' changes in pair order, scaled by each pair's share (Jacobi iterations,
// shaders/self_respond.comp), where the CPU goes through the pairs one after another. The results
// differ from the CPU's by more than rounding and are the same on every run on a device: no sum
// depends on the order of atomic operations. Pairs still touching after the rounds are reported
// (SelfContactCounts::unresolved), and stage 4, the impact zones, is the caller's: the host's self
// pass on the state read back.
#pragma once

#include <cstdint>
#include <vector>

#include "collision/self_contacts.h"
#include "core/precision.h"
#include "gpu/buffer.h"
#include "gpu/compute_pipeline.h"
#include "gpu/device.h"
#include "gpu/device_self_candidates.h"
#include "gpu/prefix_scan.h"
#include "model/cloth_model.h"

namespace clothsim::gpu {

// A ledger of the particles the passes after a step moved: each one's state before it was first
// changed ([particles][6] Reals: x, v) and a flag ([particles] words, 0 where none did), which the
// integrator's booking of the energy change reads (obstacle_energy_elements.comp).
struct MovedLedger {
  const Buffer* before = nullptr;
  const Buffer* moved = nullptr;
};

class DeviceSelfContacts {
 public:
  // For `model`'s sheet as it is now (its elements, masses and anchors, its thickness and friction).
  DeviceSelfContacts(Device& device, Precision precision, const ClothModel& model);

  // Brings this pass to the sheet `model` has now, keeping its passes and arrays: a torn sheet's
  // elements, the inverse masses of anchors set or let go and of masses edited live, the thickness
  // and the friction. False, changing nothing, where it cannot: other particles, or more elements
  // than it was made for (then make a new one). Making one compiles a dozen pipelines, which on
  // lavapipe took longer than the steps between two tears.
  bool refresh(const ClothModel& model);

  // Stages 1 to 3 after a step of `step` s from `start` to (`position`, `velocity`), [particles][3]
  // Reals each, which it changes; with a ledger, each particle it is the first to change is entered
  // there (kMovedBySelf). Returns what it did; `work` is not booked here.
  SelfContactCounts apply(const Buffer& start, const Buffer& position, const Buffer& velocity, double step,
                          const MovedLedger& ledger = {});
  // Forgets the candidates: the next apply() finds them again. A run restored at a frame then takes
  // the steps the saved one took, its candidates found at the same frame.
  void forget_candidates() { found_ = false; }

  // Device memory the pass holds for a sheet of these counts, bytes: its arrays by particle and by
  // element, and those that grow with the contact counted as the CPU counts its own
  // (SelfContacts::bytes_for: kCandidatesPerParticle candidates a particle, kGridEntriesPerBox grid
  // entries a box), each candidate listed for a response.
  static std::uint64_t bytes_for(const LatticeCounts& counts, Precision precision);

  // Stage 3's rounds of detection and response, at most (the CPU's is 8 Gauss-Seidel sweeps).
  static constexpr int kImpactRounds = 8;
  // Jacobi iterations on each round's touching pairs, and stage 2's on the near pairs.
  static constexpr int kImpactIterations = 16;
  static constexpr int kProximityIterations = 32;

 private:
  // Stage 1 and stages 2 and 3's tests over the motion start -> end, those flagged with `mask`
  // listed; their count. One submission (with `zero_counters`, the counters zeroed in it) makes the
  // tests on the candidates kept and reads back how far the particles moved; where one went past
  // the reach, the candidates are found again and a second makes the tests anew.
  std::uint32_t detect_and_list(const Buffer& start, const Buffer& end, std::uint32_t mask, bool zero_counters);
  struct Detection {
    std::uint32_t listed = 0;
    std::vector<double> motion;  // [kMotionValues] squared distances (with `motion`)
  };
  Detection submit_detection(const Buffer& start, const Buffer& end, std::uint32_t mask, bool motion,
                             bool zero_counters);
  // Room for `listed` pairs in the response arrays, and the response pass bound.
  void prepare_responses(std::uint32_t listed, const Buffer& start, const Buffer& position, const Buffer& velocity,
                         const MovedLedger& ledger);
  // Records the table from particles to the `listed` pairs and each pair's share.
  void record_table(VkCommandBuffer commands, std::uint32_t listed) const;
  void respond(VkCommandBuffer commands, std::uint32_t phase, std::uint32_t listed, bool first_round = false) const;

  Device& device_;
  Precision precision_;
  std::uint32_t particles_;
  std::size_t built_broken_;                // the model's broken connectors when last refreshed
  std::vector<double> built_inverse_mass_;  // [particles] the model's when last refreshed (0 anchored)
  double thickness_, friction_;
  double spacing_;
  DeviceSelfCandidates candidates_;
  bool found_ = false;  // candidates found at least once
  double reach_ = 0.0;  // m: how far a particle may move from found_at_ before they are found again

  Buffer inverse_mass_, found_at_, block_motion_, motion_, slot_, list_, table_start_, table_fill_, entries_, geometry_,
      change_, counters_, respond_real_, listed_;
  // Host-visible: the motion's maxima at its start, the listed pairs' count at kListedOffset, the
  // counters at kCountersOffset, as the last detection left them.
  Buffer readback_;
  static constexpr std::uint64_t kListedOffset = 16;
  static constexpr std::uint64_t kCountersOffset = 24;
  double respond_step_ = -1.0;  // s: the step respond_real_ holds (none yet)
  std::uint32_t list_capacity_ = 0;
  bool ledger_ = false;  // the bound ledger is kept
  ComputePipeline motion_pass_, list_pass_, respond_pass_;
  PrefixScan slot_scan_, table_scan_;
};

}  // namespace clothsim::gpu
