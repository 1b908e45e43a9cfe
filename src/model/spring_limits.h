// Spring limits: where a sheet tears, stretches for good or creases (DESIGN.md section 3).
//
// A material or a scene gives a handful of scalars (SpringLimits); apply_spring_limits() turns
// them into the per-spring arrays of ClothModel that the event stage (events/) reads. +infinity
// means "never": an unbreakable, perfectly elastic sheet is the default, and the paper's model is
// exactly that.
//
// Tear thresholds vary over the sheet, s_e = break_strain (1 + variation u_e) with u_e uniform
// in [-1, 1], so that a uniformly pulled sheet does not tear along a perfectly straight line of
// springs at one instant. u_e is a hash of (seed, connector index) rather than the e-th draw of a
// stream: any connector's threshold can be recomputed alone (a live edit, a checkpoint) and does
// not depend on the order in which thresholds are assigned.
#pragma once

#include <cstdint>
#include <limits>

namespace clothsim {

struct ClothModel;

struct SpringLimits {
  static constexpr double kNever = std::numeric_limits<double>::infinity();
  // Tearing: connector e breaks when its strain against its original length, l / L0_e - 1,
  // exceeds s_e = break_strain (1 + break_strain_variation u_e).
  double break_strain = kNever;         // dimensionless, > 0
  double break_strain_variation = 0.0;  // relative spread of s_e, in [0, 1)
  std::uint64_t variation_seed = 1;     // the scene's initial.seed
  // Permanent stretching: return mapping with yield strain y_e (initially yield_strain), which
  // grows by hardening times each plastic increment.
  double yield_strain = kNever;  // dimensionless, > 0
  double hardening = 0.0;        // dimensionless, >= 0
  // Creasing: a radial spring keeps |theta - theta0| <= its kind's yield angle, rad.
  double adjacent_yield_angle = kNever;  // in-plane shear that stays
  double opposite_yield_angle = kNever;  // folds that stay

  // True when a law can change the sheet during a run (some limit is finite).
  bool changes_sheet() const {
    return break_strain != kNever || yield_strain != kNever || adjacent_yield_angle != kNever ||
           opposite_yield_angle != kNever;
  }
  bool operator==(const SpringLimits&) const = default;
};

// The one rule between the limits: a finite yield strain above the break strain would never be
// reached (tearing is measured against the original length, events/spring_events.h), so it is
// refused. An elastic connector (yield +inf) may have any break strain.
inline bool yields_after_breaking(double yield_strain, double break_strain) {
  return yield_strain != SpringLimits::kNever && yield_strain > break_strain;
}

// u_e in [-1, 1]: a fixed function of (seed, connector) (SplitMix64 of their combination).
double break_strain_offset(std::uint64_t seed, std::uint64_t connector);

// s_e of connector `connector` under `limits` (+inf when break_strain is).
double connector_break_threshold(const SpringLimits& limits, std::uint64_t connector);

// Sets every connector's break threshold and yield strain and every radial spring's yield angle
// from `limits` (a yield strain already grown by hardening is reset to limits.yield_strain), and
// records `limits` in the model. Rest values and broken springs are left as they are. Goes
// through the model's revision like every edit (model/model_edits.h).
void apply_spring_limits(ClothModel& model, const SpringLimits& limits);

}  // namespace clothsim
