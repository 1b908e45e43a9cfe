// The setup tests share to run a scene: its model, its initial state and its integrator, on one
// thread (so that figures do not depend on the machine's load). The library has no single entry
// point for this yet (issue 10's make_simulation); when it does, this becomes a call to it.
#pragma once

#include <utility>

#include "scene/scene.h"
#include "sim/simulation.h"

namespace clothsim::testing {

// `model` is build_model(spec), possibly edited by the test (a collider added) before the run.
inline Simulation one_thread_simulation(const SceneSpec& spec, ClothModel model) {
  SimulationSettings settings;
  settings.integrator = spec.integrator;
  settings.threads = 1;
  ClothState initial = build_initial_state(model, spec);
  return Simulation(std::move(model), std::move(initial), settings);
}

inline Simulation one_thread_simulation(const SceneSpec& spec) {
  return one_thread_simulation(spec, build_model(spec));
}

}  // namespace clothsim::testing
