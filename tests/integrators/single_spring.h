// The smallest cloth ODE with a known answer, for the integrators' tests: two particles joined by
// the paper's connector, particle 0 anchored at its rest position (-L/2, 0, 0), no gravity. Along
// the spring it is a linear (damped) oscillator; swinging in a plane it is nonlinear.
#pragma once

#include <gtest/gtest.h>

#include "integrators/integrator.h"
#include "model/cloth_model.h"

namespace clothsim::single_spring {

inline constexpr double kStiffness = 80.0;  // N/m, the paper's connector
inline constexpr double kMass = 1.0;        // kg
inline constexpr double kRest = 1.0;        // m

// The model, with the connector's damping (N s/m).
inline ClothModel model(double damping) {
  LatticeDef def;
  def.rows = 1;
  def.cols = 2;
  def.spacing = kRest;
  def.particle_mass = kMass;
  def.connector = {kStiffness, damping};
  const Anchor anchor{0, AnchorPath::fixed_at({-kRest / 2, 0, 0})};
  return build_lattice(def, Environment{{0, 0, 0}, 0.0}, {&anchor, 1});
}

// The rest state with particle 1 moved by `amplitude` along the spring, at `velocity`.
inline ClothState displaced(const ClothModel& model, double amplitude, Vec3 velocity = {}) {
  ClothState state = make_rest_state(model);
  state.position[1].x += amplitude;
  state.velocity[1] = velocity;
  return state;
}

// Runs `integrator` from `state` to `end`; a step that fails fails the test and ends the run.
inline ClothState run(Integrator& integrator, ClothState state, double end) {
  while (state.time < end) {
    const StepOutcome outcome = integrator.step(state, end);
    EXPECT_EQ(outcome.status, StepStatus::ok);
    if (outcome.status != StepStatus::ok) break;
  }
  return state;
}

}  // namespace clothsim::single_spring
