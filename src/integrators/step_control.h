// The C++ spelling of integrators/step_control.inc: the PI step-size controller and the clipping
// of a step to a target time, the text the device's rk_control.comp compiles as well.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/shared_text.h"
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

}  // namespace clothsim::step_control
