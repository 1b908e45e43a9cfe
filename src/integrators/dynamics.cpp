#include "integrators/dynamics.h"

#include "core/parallel.h"
#include "core/timer.h"

namespace clothsim {

void StateDerivative::resize(std::size_t particles) {
  position_rate.assign(particles, Vec3{});
  velocity_rate.assign(particles, Vec3{});
}

ClothDynamics::ClothDynamics(const ClothModel& model, const ForceOptions& options)
    : model_(model), options_(options), force_(model.particle_count()) {
  buffers_.kernel = options.kernel;
  buffers_.resize(model);
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
  const ForcePowers powers =
      evaluate_forces(model_, position, velocity, options_.terms, options_.threads, buffers_, force_);
  const ClothModel& model = model_;
  const std::span<const Vec3> force = force_;
  parallel_for(model.particle_count(), options_.threads, [&](std::size_t p) {
    out.position_rate[p] = velocity[p];
    out.velocity_rate[p] = model.particle_inverse_mass[p] * force[p];
  });
  // Anchors: the path's acceleration, and the power of the force the anchor must exert to keep
  // the particle on its path, m a - f, which is the work the anchor does on the sheet.
  double anchor_power = 0.0;
  for (const Anchor& anchor : model.anchors) {
    const std::uint32_t p = anchor.particle;
    const Vec3 acceleration = anchor.path.acceleration(time);
    out.velocity_rate[p] = acceleration;
    anchor_power += dot(velocity[p], model.particle_mass[p] * acceleration - force[p]);
  }
  out.damping_power = powers.damping;
  out.drag_power = powers.drag;
  out.anchor_power = anchor_power;
}

double clip_step(double time, double step, double t_limit, bool& clipped) {
  // A step that would leave less than a millionth of itself before t_limit is stretched to end
  // there: otherwise the next step would be a sliver decided by rounding.
  const double remaining = t_limit - time;
  clipped = step >= remaining * (1.0 - 1e-6);
  return clipped ? remaining : step;
}

}  // namespace clothsim
