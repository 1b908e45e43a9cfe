// The C++ spelling of integrators/step_control.inc: the PI step-size controller and the clipping
// of a step to a target time, the text the device's rk_control.comp compiles as well.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>

#include "core/shared_text.h"
#include "core/state_archive.h"
#include "integrators/integrator.h"

namespace clothsim::step_control {

using Real = double;
using StepFactor = double;
using std::clamp;
using std::max;
using std::min;
using std::pow;

#include "integrators/step_control.inc"

// A controller with `settings`' safety, growth and shrink, before its first step.
inline StepController make_step_controller(const IntegratorSettings& settings) {
  return {settings.safety, settings.max_growth, settings.max_shrink, 0.0, 1e-4, false};
}

// A controller's memory between steps (its next step and its last error), saved and restored as
// `prefix`.proposed_step and `prefix`.previous_error, for an adaptive integrator's checkpoint.
inline void transfer_controller(StateArchive& archive, std::string_view prefix, StepController& controller) {
  const std::string name(prefix);
  archive.value(name + ".proposed_step", controller.proposed_step);
  archive.value(name + ".previous_error", controller.previous_error);
}

}  // namespace clothsim::step_control
