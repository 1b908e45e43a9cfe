// The setup tests share to run a scene: the library's make_simulation (scene/scene_simulation.h)
// on one thread, so that figures do not depend on the machine's load.
#pragma once

#include <utility>

#include "scene/scene.h"
#include "scene/scene_simulation.h"
#include "sim/simulation.h"

namespace clothsim::testing {

// `model` is build_model(spec), possibly edited by the test (a collider added) before the run.
inline Simulation one_thread_simulation(SceneSpec spec, ClothModel model) {
  spec.threads = 1;
  return make_simulation(spec, std::move(model));
}

inline Simulation one_thread_simulation(const SceneSpec& spec) {
  return one_thread_simulation(spec, build_model(spec));
}

}  // namespace clothsim::testing
