// Every built-in scene, run whole with its own integrator and frame rate as `clothsim run` does,
// completes: none trips the blow-up check on the energy balance (integrator.energy_error_limit,
// sim/simulation.h), the explosion check or the step floor (issue 11).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "scene_simulation.h"
#include "sim/simulation.h"

namespace clothsim {
namespace {

std::vector<std::string> builtin_names() {
  std::vector<std::string> names;
  for (const BuiltinScene& scene : builtin_scenes()) names.emplace_back(scene.name);
  return names;
}

class BuiltinRun : public ::testing::TestWithParam<std::string> {};

TEST_P(BuiltinRun, CompletesWithoutTrippingTheChecks) {
  const SceneSpec spec = builtin_scene(GetParam());
  Simulation simulation = testing::one_thread_simulation(spec);
  const auto frames = static_cast<int>(std::llround(spec.output.duration * spec.output.fps));
  for (int frame = 1; frame <= frames; ++frame) {
    ASSERT_TRUE(simulation.advance_to(static_cast<double>(frame) / spec.output.fps))
        << simulation.failure()->message;
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, BuiltinRun, ::testing::ValuesIn(builtin_names()),
                         [](const ::testing::TestParamInfo<std::string>& scene_info) {
                           std::string name = scene_info.param;
                           for (char& c : name) {
                             if (c == '-') c = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace clothsim
