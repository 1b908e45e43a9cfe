// Simulation settings the sim tests share: one thread (so results do not depend on the machine)
// and the integrator under test.
#pragma once

#include "sim/simulation.h"

namespace clothsim::testing {

// RKF45 with relative and absolute tolerance `tolerance`.
inline SimulationSettings rkf45(double tolerance) {
  SimulationSettings settings;
  settings.integrator.relative_tolerance = tolerance;
  settings.integrator.absolute_tolerance = tolerance;
  settings.threads = 1;
  return settings;
}

// Fixed-step RK4 with step `step`, s.
inline SimulationSettings rk4(double step) {
  SimulationSettings settings;
  settings.integrator.kind = IntegratorKind::rk4;
  settings.integrator.time_step = step;
  settings.threads = 1;
  return settings;
}

}  // namespace clothsim::testing
