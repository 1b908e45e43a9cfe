#include "integrators/symplectic_euler.h"

#include <algorithm>

#include "core/assert.h"
#include "core/parallel.h"
#include "core/step_profile.h"

namespace clothsim {

SymplecticEuler::SymplecticEuler(const ClothModel& model, const IntegratorSettings& settings,
                                 const ForceOptions& options)
    : model_(model), settings_(settings), dynamics_(model, options) {
  rate_.resize(model.particle_count());
}

StepOutcome SymplecticEuler::step(ClothState& state, double t_limit) {
  CLOTHSIM_ASSERT(t_limit > state.time, "step() needs a limit after the current time");
  bool clipped = false;
  const double h = clip_step(state.time, settings_.time_step, t_limit, clipped);
  dynamics_.evaluate(state.time, state.position, state.velocity, rate_);
  {
    StageTimer timer(profile_, StepStage::solution_update);
    parallel_for(model_.particle_count(), dynamics_.threads(), [&](std::size_t p) {
      state.velocity[p] += h * rate_.velocity_rate[p];
      state.position[p] += h * state.velocity[p];
    });
  }
  // The work integrals take the rates at the start of the step (first order, like the method).
  state.damping_work += h * rate_.damping_power;
  state.drag_work += h * rate_.drag_power;
  state.anchor_work += h * rate_.anchor_power;
  state.time = clipped ? t_limit : state.time + h;
  dynamics_.constrain(state.time, state.position, state.velocity);

  count_evaluations(dynamics_.evaluations());
  profile_.set(StepStage::forces, dynamics_.seconds());
  for (std::size_t p = 0; p < model_.particle_count(); ++p) {
    if (!is_finite(state.position[p]) || !is_finite(state.velocity[p])) {
      return {StepStatus::non_finite, h, static_cast<std::uint32_t>(p), true};
    }
  }
  record_accepted_step(h);
  return {StepStatus::ok, h, 0, false};
}

}  // namespace clothsim
