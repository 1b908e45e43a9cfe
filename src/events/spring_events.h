// The event stage: tearing, permanent stretching and creasing, between accepted steps.
//
// The laws are those of DESIGN.md section 3, applied to the accepted state after each step, in
// this order:
//   1. tearing     connector e breaks when its strain against its original length,
//                  l / L0_e - 1, exceeds its threshold s_e (model/spring_limits.h); the radial
//                  springs that use it break with it. All breaks found after a step are applied
//                  together, in connector index order.
//   2. stretching  each intact connector: elastic strain eps = l / L_e - 1 against its current
//                  rest length; if |eps| > y_e, the plastic increment is d = |eps| - y_e, the rest
//                  length becomes L_e = l / (1 + sign(eps) y_e) and y_e grows by hardening d.
//   3. creasing    each intact radial spring: if |theta - theta0| > a, theta0 becomes
//                  theta - sign(theta - theta0) a, kept in [0, pi].
// Tearing is measured against the original length, not the plastic rest length: the return
// mapping caps the elastic strain at the yield strain, so a connector that yields would never
// reach a break strain above its yield (and a yield above the break strain is refused as input);
// what paper and film tests report as elongation at break (ISO 1924-2, ASTM D882) is the total
// strain. For an elastic sheet the two are the same (docs/model.md).
//
// Determinism: each spring's check depends only on the state and that spring, so the checks run
// in parallel into one flag byte per spring, and the laws then act in index order on one thread
// (on most steps on no spring at all): the same changes and the same released energy, summed in
// the same order, for any thread count.
//
// Energy: a change at fixed positions changes the elastic energy by dE = E_after - E_before
// (never positive here: a break removes a spring's energy, a return mapping moves the rest value
// towards the current one). dE is added to ClothState::fracture_work (breaks) or plastic_work
// (stretching, creasing), so the balance of sim/ stays a measure of integration error.
//
// A stage whose limit is +infinity in the model's SpringLimits is skipped: an elastic,
// unbreakable sheet (the paper's) pays nothing here.
//
// Cost. Creasing needs every radial spring's angle after every step, and an arctangent per
// spring costs about as much as a force evaluation. Since cos is decreasing on [0, pi],
// |theta - theta0| > a exactly when cos(theta) < cos(theta0 + a) or cos(theta) > cos(theta0 - a);
// the stage keeps those two bounds per spring (recomputed when the model changes from outside, and
// for each spring it creases) and compares cos(theta) against them with a margin of 1e-12, far
// above cos(theta)'s rounding. Only the springs within the margin or past a bound get the
// arctangent and the law; a spring the test skips is at least ~1e-6 rad inside its yield angle.
// cos(theta) is the dot product of the two connectors' unit vectors, which one pass over the
// connectors computes (with their lengths, for the other two laws): one square root per
// connector, not one per radial spring.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/vec3.h"
#include "model/cloth_model.h"

namespace clothsim {

// What one application of the event stage changed.
struct SpringEventCounts {
  std::size_t breaks = 0;   // connectors broken
  std::size_t yields = 0;   // connectors whose rest length changed
  std::size_t creases = 0;  // radial springs whose rest angle changed
  bool any() const { return breaks + yields + creases > 0; }

  template <typename Self, typename Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit("breaks", self.breaks);
    visit("yields", self.yields);
    visit("creases", self.creases);
  }
};

// Breaks `connector` (with its radial springs) at `state`'s time and books the elastic energy
// this releases at `state`'s positions, its own and that of its radial springs still intact, as
// fracture work. The one way a connector breaks, whether the tearing law or a cut breaks it.
// Returns false (and changes nothing) if it was broken already.
bool tear_connector(ClothModel& model, ClothState& state, std::uint32_t connector);

// Scratch of the event stage, sized for one model on first use; apply() does not allocate after.
class SpringEvents {
 public:
  // Applies the three laws to `state`'s positions, changing `model` through model/model_edits.h
  // and adding the released energy to state.fracture_work and state.plastic_work.
  SpringEventCounts apply(ClothModel& model, ClothState& state, int threads);
  // Bytes of scratch memory held.
  std::size_t bytes() const {
    return connector_flag_.capacity() + radial_flag_.capacity() + connector_unit_.capacity() * sizeof(Vec3) +
           (radial_orientation_.capacity() + cos_upper_.capacity() + cos_lower_.capacity()) * sizeof(double);
  }
  // The bytes bytes() reports once apply() has run with a finite limit on the lattice of `counts`
  // (sim/memory_estimate.h); none while every limit is infinite.
  static std::size_t bytes_for(const LatticeCounts& counts) {
    return counts.connectors * (sizeof(std::uint8_t) + sizeof(Vec3)) +
           counts.radials * (sizeof(std::uint8_t) + 3 * sizeof(double));
  }

 private:
  void resize(const ClothModel& model);
  // The crease bounds of radial spring r from its rest and yield angles.
  void set_crease_bounds(const ClothModel& model, std::size_t r);
  // What the parallel checks found, per spring: the laws that may act on it.
  static constexpr std::uint8_t kBreaks = 1;
  static constexpr std::uint8_t kYields = 2;
  std::vector<std::uint8_t> connector_flag_;  // [connectors] kBreaks | kYields
  std::vector<std::uint8_t> radial_flag_;     // [radials] 1: check the crease law
  std::vector<Vec3> connector_unit_;          // [connectors] from its first particle to its second (creasing only)
  std::vector<double> radial_orientation_;    // [radials] sign that turns the connectors' dot product into cos(theta)
  std::vector<double> cos_upper_;             // [radials] cos(theta0 + a): below it the spring creases (-2: never)
  std::vector<double> cos_lower_;             // [radials] cos(theta0 - a): above it the spring creases (+2: never)
  std::uint64_t bounds_revision_ = ~0ull;     // model revision the bounds were computed at
};

}  // namespace clothsim
