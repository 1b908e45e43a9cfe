#include "integrators/dynamics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/parallel.h"
#include "core/timer.h"
#include "integrators/step_control.h"

namespace clothsim {

void StateDerivative::resize(std::size_t particles) { velocity_rate.assign(particles, Vec3{}); }

ClothDynamics::ClothDynamics(const ClothModel& model, const ForceOptions& options) : model_(model), options_(options) {
  buffers_.kernel = options.kernel;
  buffers_.precision = options.precision;
  buffers_.both_precisions = options.both_precisions;
  buffers_.resize(model);
}

void ClothDynamics::set_precision(Precision precision) {
  buffers_.set_precision(model_, precision);
  options_.precision = precision;
}

double ClothDynamics::float32_rounding(double time, std::span<const Vec3> position, std::span<const Vec3> velocity,
                                       StateDerivative& exact, StateDerivative& rounded) {
  const Precision kept = precision();
  set_precision(Precision::float64);
  evaluate(time, position, velocity, exact);
  set_precision(Precision::float32);
  evaluate(time, position, velocity, rounded);
  set_precision(kept);
  // An anchored particle's acceleration is its path's in both.
  double largest = 0.0;
  for (std::size_t p = 0; p < exact.velocity_rate.size(); ++p) {
    const double difference = norm(rounded.velocity_rate[p] - exact.velocity_rate[p]);
    if (!std::isfinite(difference)) return std::numeric_limits<double>::infinity();
    largest = std::max(largest, difference);
  }
  return largest;
}

void ClothDynamics::constrain(double time, std::span<Vec3> position, std::span<Vec3> velocity) const {
  for (const Anchor& anchor : model_.anchors) {
    position[anchor.particle] = anchor.path.position(time);
    velocity[anchor.particle] = anchor.path.velocity_at(time);
  }
}

void ClothDynamics::evaluate(double time, std::span<const Vec3> position, std::span<const Vec3> velocity,
                             StateDerivative& out) {
  ScopedTimer timer(seconds_);
  ++evaluations_;
  // The forces go straight into the acceleration array and are divided by the masses in place.
  const std::span<Vec3> acceleration = out.velocity_rate;
  const ForcePowers powers =
      evaluate_forces(model_, position, velocity, options_.terms, options_.threads, buffers_, acceleration);
  const ClothModel& model = model_;
  // Anchors: the power of the force the anchor must exert to keep the particle on its path,
  // m a - f, which is the work the anchor does on the sheet; f is read before it is divided.
  double anchor_power = 0.0;
  for (const Anchor& anchor : model.anchors) {
    const std::uint32_t p = anchor.particle;
    anchor_power += dot(velocity[p], model.particle_mass[p] * anchor.path.acceleration(time) - acceleration[p]);
  }
  parallel_for(model.particle_count(), options_.threads,
               [&](std::size_t p) { acceleration[p] = model.particle_inverse_mass[p] * acceleration[p]; });
  // An anchored particle's acceleration is its path's.
  for (const Anchor& anchor : model.anchors) acceleration[anchor.particle] = anchor.path.acceleration(time);
  out.damping_power = powers.damping;
  out.drag_power = powers.drag;
  out.anchor_power = anchor_power;
}

double clip_step(double time, double step, double t_limit, bool& clipped) {
  const step_control::ClippedStep result = step_control::clip_step(time, step, t_limit);
  clipped = result.clipped;
  return result.step;
}

}  // namespace clothsim
