// `precision: auto` on the CPU, frame by frame: float32 forces where they stay close to float64's,
// float64 where they do not.
//
// float32 springs (forces/lattice_kernel.h, "Precision") differ from float64's in two ways: they
// round each spring's force to about 6e-8 of itself, so the error of a particle's acceleration
// grows with the loads on its springs and with their stiffness; and below sin(theta) = 1e-6 they
// take a straight spring's other one-sided limit (forces/lattice_spring.h, SingularLimits), which
// on a large sheet that stays flat for a while sends it into another buckling mode (measured: 128 x
// 128 of the paper's material 1.9 mm from the exact motion after 1 s, where float64 stays within
// 0.35 mm; float64 with float's threshold follows float32). `auto`'s rule (sim/backend.h) reads the
// tolerances only. So a run that starts in float32 on `auto` measures both at the start of each
// window of simulated time: it evaluates the forces at the state once in each precision
// (ClothDynamics::float32_rounding), takes the largest difference of a particle's acceleration,
// delta, and bounds the distance that difference, held over the window, moves a particle:
//   drift = delta W^2 / 2,   W = kPrecisionWindow (a frame at 60 frames per second).
// The window runs in float32 where 0 < drift <= kFloat32DriftFraction * absolute_tolerance, else
// in float64. Where the two evaluations agree to the bit (a sheet at rest, its springs at their
// rest values) they say nothing of the steps to come, which then start from the rest state in both
// precisions' branches: one step in float64, and a new window after it. A window starts at each
// Simulation::advance_to() and again every W within it, at the first step from then on, so the
// choice depends on the state alone: a resumed run and any thread count choose alike. It costs
// two force evaluations a window (RKF45 takes about 190 a frame of the paper's material).
//
// Why a bound and not the error itself: the difference between the precisions at a state is
// deterministic and changes slowly with the state, so over a window it acts like a constant force
// error, which moves a free particle by delta t^2 / 2; a particle held by springs moves less. A
// quarter of atol a window: on the paper's Figures 5 and 6 (drift up to 6.6e-8 m) every window
// is float32; a sheet 30 times stiffer changes back and forth; 100 times stiffer, and the flat
// 128 x 128 sheet, are float64 (drift 2.6e-5 to 2.5e-4 m). docs/performance.md, "`precision: auto`
// frame by frame", has the measurements behind both constants.
#pragma once

#include <cstdint>
#include <limits>

#include "core/precision.h"
#include "core/record_fields.h"
#include "core/state_archive.h"
#include "integrators/integrator.h"

namespace clothsim {

inline constexpr double kPrecisionWindow = 1.0 / 60.0;  // s
inline constexpr double kFloat32DriftFraction = 0.25;   // of the absolute tolerance

// What the choice did over a run, reported in summary.json.
struct PrecisionChoiceStats {
  std::uint64_t float32_windows = 0;
  std::uint64_t float64_windows = 0;
  std::uint64_t rest_steps = 0;  // steps in float64 from a state the two precisions agree on
  double largest_drift = 0.0;    // m, the largest drift measured at a window's start

  // Every field, in order (core/record_fields.h).
  template <typename Self, typename Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit("float32_windows", self.float32_windows);
    visit("float64_windows", self.float64_windows);
    visit("rest_steps", self.rest_steps);
    visit("largest_drift", self.largest_drift);
  }
};

class PrecisionChoice {
 public:
  PrecisionChoice() = default;
  // `active`: the run chooses frame by frame (BackendSettings::chooses_by_frame); `absolute_tolerance`
  // sets the drift limit. The statistics stay across calls.
  void configure(bool active, double absolute_tolerance);
  bool active() const { return active_; }
  // The drift limit, m.
  double drift_limit() const { return limit_; }
  // Starts an advance: its first step starts a window.
  void begin_advance() { window_end_ = -std::numeric_limits<double>::infinity(); }
  // Before each step: where a window starts at `state`, measures the rounding with `integrator`
  // and sets its forces' precision for the window.
  void before_step(Integrator& integrator, const ClothState& state);
  const PrecisionChoiceStats& stats() const { return stats_; }
  // The statistics, for checkpoints (the window in progress ends with the advance that saves).
  void transfer_state(StateArchive& archive);

 private:
  bool active_ = false;
  double limit_ = 0.0;
  double window_end_ = -std::numeric_limits<double>::infinity();
  PrecisionChoiceStats stats_;
};

}  // namespace clothsim
