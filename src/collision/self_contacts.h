// The collision stage's self-collision pass: the sheet against itself, between accepted steps,
// after the obstacle pass. docs/collisions.md ("Self-collision") has the stages in full, the
// guarantee's tests and the choices with their reasons.
//
// The sheet is its lattice triangles and their edges (collision/sheet_elements.h). Two kinds of
// pairs can meet: a particle and a triangle it is no corner of, and two edges that share no
// particle. Every pair is written the same way, as 4 particles and 4 signed weights c_k whose sum
// q = sum_k c_k x_k is the vector between the pair's two nearest points (from the triangle's or
// the second edge's to the particle's or the first edge's): (1, -a, -b, -c) with the nearest
// point's barycentric weights (a, b, c), or (1-s, s, -(1-t), -t) with the edges' parameters. A
// change of q along a unit normal n by D, spread over the 4 particles by inverse mass w_k, moves
// particle k by (D / K) c_k w_k n, with K = sum_k c_k^2 w_k: the smallest mass-weighted change
// that does it, and one that keeps the pair's momentum (Bridson, Fedkiw and Anderson, "Robust
// treatment of collisions, contact and friction for cloth animation", SIGGRAPH 2002, section 7.1).
//
// With the step's start positions x0 (a state where the sheet does not cross itself) and the
// accepted step's end positions x1, the pass runs four stages:
//   1. candidates  pairs whose boxes over the step, grown by the thickness h plus a reach r,
//                  overlap (a hashed grid, collision/box_grid.h), kept over the next steps while
//                  no particle moves further than r;
//   2. proximity   pairs nearer than h at x0 or x1 are held on the side they were on at x0, h
//                  apart (the direction measured at x0), with inelastic contact and Coulomb
//                  friction;
//   3. impacts     continuous detection along x0 -> x1 by conservative advancement; a pair that
//                  comes within touching distance has its closing motion removed for the step,
//                  for at most kImpactRounds rounds;
//   4. zones       the fail-safe: the particles of pairs still touching move as rigid groups
//                  (impact zones; Provot 1997, Bridson et al. 2002 section 7.4, translating only).
// So a sheet that did not cross itself at the step's start does not cross itself at its end.
// Anchored particles have no inverse mass: the pass does not move them; particles on an obstacle
// move like any other (collision/collision_stage.h puts them back out).
//
// Determinism: the candidates are found in fixed blocks and concatenated in block order, the
// tests of stages 2 to 4 run in parallel but only write flags, and every change is made serially
// in candidate order; the results are the same for any thread count.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "collision/box_grid.h"
#include "collision/contact_energy.h"
#include "collision/sheet_elements.h"
#include "core/vec3.h"
#include "forces/forces.h"
#include "model/cloth_model.h"

namespace clothsim {

// A pair of sheet elements that may meet: a particle and a triangle, or two edges.
struct SelfPair {
  enum class Kind : std::uint8_t { point_triangle, edge_edge };
  std::array<std::uint32_t, 4> particle{};  // (point, a, b, c) or (a, b, c, d)
  std::array<std::uint32_t, 2> element{};   // (particle, triangle) or (edge, edge) of SheetElements
  Kind kind = Kind::point_triangle;
  bool operator==(const SelfPair&) const = default;
};

// The pair's distance and unit normal at positions `x` of its 4 particles (the normal is q / |q|,
// zero when q is), and its 4 signed weights.
struct PairGeometry {
  double distance = 0.0;
  Vec3 normal;
  std::array<double, 4> weight{};
};
// What one self-collision pass did.
struct SelfContactCounts {
  std::size_t contacts = 0;    // pairs within the thickness at the step's end, pushed apart
  std::size_t impacts = 0;     // pairs whose motion touched, stopped along their normal (stage 3)
  std::size_t zones = 0;       // impact zones moved as one (stage 4)
  std::size_t unresolved = 0;  // pairs still touching after stage 4's rounds (none expected)
  double work = 0.0;           // energy change the pass caused, J (also added to state.contact_work)
};

class SelfContacts {
 public:
  // After the step of length `step` from `start` [particle_count()]: stages 1 to 4 on `state`
  // (see the top of the file), the energy change booked in state.contact_work.
  SelfContactCounts apply(const ClothModel& model, ClothState& state, std::span<const Vec3> start, double step,
                          ForceTerms terms, int threads);

  // Stage 1 alone: the candidate pairs of elements at `start` -> `end` with boxes grown by
  // `margin`, in the pass's order (for tests; the pass keeps them in candidates()).
  void find_candidates(const ClothModel& model, std::span<const Vec3> start, std::span<const Vec3> end, double margin,
                       int threads);
  std::span<const SelfPair> candidates() const { return candidates_; }
  const SheetElements& elements() const { return elements_; }
  std::size_t bytes() const;

  // Stage 1's reach (m): how far particles may move from where the candidates were found before
  // they are found again, for a step in which they moved at most `moved` m, after a last reach of
  // `last_reach` (0 for none), on a lattice of `spacing` m. The device's pass takes it too.
  static double candidate_reach(double moved, double last_reach, double thickness, double spacing);
  // The distance (m) at the step's end positions beyond which a candidate found with that reach
  // is dropped: it cannot come within the thickness before the candidates are found again.
  static double prune_distance(double moved, double reach, double thickness);

  // The bytes the pass holds on the lattice of `counts` (sim/memory_estimate.h): its per-particle
  // and per-element arrays, the two grids, and the candidate pairs. The number of candidates and
  // of grid entries depends on how the sheet lies and how fast it moves, so those two are
  // allowances, measured (docs/performance.md, "Memory"): a flat sheet falling finds about 9
  // candidates per particle, `pile` about 40 while it folds, and up to 233 for the few steps
  // of its impact on the rod. The estimate takes 40; an impact can need more for a moment.
  static std::size_t bytes_for(const LatticeCounts& counts);
  static constexpr double kCandidatesPerParticle = 40.0;
  static constexpr double kGridEntriesPerBox = 4.0;

 private:
  // The boxes of the motion start -> end of every particle, triangle and edge, grown by `margin`:
  // point_box_, triangle_box_, edge_box_.
  void motion_boxes(std::span<const Vec3> start, std::span<const Vec3> end, double margin, int threads);
  // Stage 1's search: the candidate pairs into block_pairs_, each block's in the pass's order.
  void search(const ClothModel& model, std::span<const Vec3> start, std::span<const Vec3> end, double margin,
              int threads);
  // Drops from block_pairs_ the pairs at least `reach` apart at x, each block keeping its order.
  void prune_blocks(std::span<const Vec3> x, double reach, int threads);
  // candidates_ <- block_pairs_ joined in block order.
  void join_blocks(int threads);
  // list_ <- the active candidates k with flag[k] != 0, in order.
  void select_flagged(std::span<const std::uint8_t> flag, int threads);
  void select_active(std::span<const Vec3> start, std::span<const Vec3> end, double thickness, int threads);
  void detect_proximity(std::span<const Vec3> start, std::span<const Vec3> end, double thickness, int threads);
  std::size_t resolve_proximity(const ClothModel& model, ClothState& state, double step);
  bool resolve_impacts(const ClothModel& model, ClothState& state, std::span<const Vec3> start,
                       SelfContactCounts& counts, int threads);
  void move_zones(const ClothModel& model, ClothState& state, std::span<const Vec3> start, SelfContactCounts& counts,
                  int threads);
  // Flags in touching_ the candidates whose motion start -> state.position touches; their count.
  std::size_t detect_impacts(std::span<const Vec3> start, std::span<const Vec3> end, double thickness, int threads);
  // Finds the candidates again unless those kept still hold every pair of the motion start -> end,
  // then picks the active ones: those whose elements' boxes over that motion, grown by half the
  // thickness, overlap (the others can neither be within the thickness nor touch).
  void refresh_candidates(const ClothModel& model, std::span<const Vec3> start, std::span<const Vec3> end, int threads);

  SheetElements elements_;
  BoxGrid triangle_grid_;
  BoxGrid edge_grid_;
  std::vector<Box> point_box_;                      // [particles]
  std::vector<Box> triangle_box_;                   // [triangles]
  std::vector<Box> edge_box_;                       // [edges]
  std::vector<std::vector<SelfPair>> block_pairs_;  // stage 1's output per block of queries
  std::vector<std::size_t> block_start_;            // [blocks + 1] where each block's pairs start in candidates_
  std::vector<SelfPair> candidates_;
  std::vector<std::uint8_t> active_flag_;    // [candidates] scratch flags of the selection
  std::vector<std::uint32_t> active_;        // active candidates, in order
  std::vector<double> start_distance_;       // [active] m, each active pair's distance at the step's start
  bool selection_current_ = false;           // active_ was selected in this pass
  std::vector<Vec3> selected_at_;            // [particles] end positions the active pairs were selected for
  std::vector<Vec3> found_at_;               // [particles] end positions the candidates were found for
  double found_thickness_ = 0.0;             // m, the thickness they were found for
  double found_reach_ = 0.0;                 // m, how far particles may move before they are found again
  std::vector<double> inverse_mass_;         // [particles] 0 for anchored particles
  std::vector<std::uint8_t> near_;           // [active] 1: within the thickness at x0 or x1, apart at x0
  std::vector<PairGeometry> near_geometry_;  // [list_] each near pair at the step's start
  std::vector<std::uint8_t> touching_;       // [active] 1: its motion touches
  std::vector<std::uint32_t> list_;          // flagged candidates, in order
  std::vector<std::uint32_t> zone_parent_;   // [particles] union-find of stage 4
  std::vector<Vec3> before_position_;        // [particles] state at the pass's start
  std::vector<Vec3> before_velocity_;
  std::vector<std::uint8_t> changed_;  // [particles] 1: the pass changed it
  ContactEnergy energy_;
};

PairGeometry measure_pair(SelfPair::Kind kind, const std::array<Vec3, 4>& x);

}  // namespace clothsim
