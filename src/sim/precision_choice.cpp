#include "sim/precision_choice.h"

#include <algorithm>
#include <optional>

namespace clothsim {

void PrecisionChoice::configure(bool active, double absolute_tolerance) {
  active_ = active;
  limit_ = kFloat32DriftFraction * absolute_tolerance;
  begin_advance();
}

void PrecisionChoice::before_step(Integrator& integrator, const ClothState& state) {
  if (!active_ || state.time < window_end_) return;
  const std::optional<double> delta = integrator.float32_acceleration_error(state);
  if (!delta) return;  // an integrator without float32 forces keeps its own
  // Where the two precisions agree to the bit (a sheet at rest, its springs at their rest values),
  // the measurement says nothing of the steps to come: one step in float64, then a new window.
  const bool measured = *delta > 0.0;
  window_end_ = measured ? state.time + kPrecisionWindow : state.time;
  const double drift = 0.5 * *delta * kPrecisionWindow * kPrecisionWindow;
  // Non-finite forces give an infinite drift: float64 (and the step's checks diagnose them).
  const bool float32 = measured && drift <= limit_;
  integrator.set_force_precision(float32 ? Precision::float32 : Precision::float64);
  ++(!measured ? stats_.rest_steps : float32 ? stats_.float32_windows : stats_.float64_windows);
  stats_.largest_drift = std::max(stats_.largest_drift, drift);
}

void PrecisionChoice::transfer_state(StateArchive& archive) { transfer_fields(archive, "precision_choice", stats_); }

}  // namespace clothsim
