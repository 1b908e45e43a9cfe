// Every built-in scene, run whole with its own integrator and frame rate as `clothsim run` does,
// completes: none trips the blow-up check on the energy balance (integrator.energy_error_limit,
// sim/simulation.h), the explosion check or the step floor (issue 11).
//
// CLOTHSIM_TEST_RUN_FRACTION in the environment, a number in (0, 1], runs each scene's first
// fraction of frames instead, with the same assertion. The sanitize test preset sets 0.25
// (docs/testing.md, "The sanitizer suite"): under AddressSanitizer and UBSan a step costs about 7
// times as much, and the scenes run whole would take half of the sanitized suite's time. The
// release suite runs them whole.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene_simulation.h"
#include "sim/simulation.h"
#include "test_support.h"

namespace clothsim {
namespace {

std::vector<std::string> builtin_names() {
  std::vector<std::string> names;
  for (const BuiltinScene& scene : builtin_scenes()) names.emplace_back(scene.name);
  return names;
}

// The fraction of each run to simulate: 1 unless CLOTHSIM_TEST_RUN_FRACTION says otherwise.
double run_fraction() {
  const char* text = std::getenv("CLOTHSIM_TEST_RUN_FRACTION");
  if (text == nullptr) return 1.0;
  char* end = nullptr;
  const double fraction = std::strtod(text, &end);
  if (end == text || *end != '\0' || !(fraction > 0.0 && fraction <= 1.0)) {
    ADD_FAILURE() << "CLOTHSIM_TEST_RUN_FRACTION must be a number in (0, 1], got \"" << text << "\"";
    return 1.0;
  }
  return fraction;
}

class BuiltinRun : public ::testing::TestWithParam<std::string> {};

TEST_P(BuiltinRun, CompletesWithoutTrippingTheChecks) {
  const SceneSpec spec = builtin_scene(GetParam());
  Simulation simulation = testing::one_thread_simulation(spec);
  const auto frames =
      std::max(1, static_cast<int>(std::llround(spec.output.duration * spec.output.fps * run_fraction())));
  for (int frame = 1; frame <= frames; ++frame) {
    ASSERT_TRUE(simulation.advance_to(static_cast<double>(frame) / spec.output.fps)) << simulation.failure()->message;
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, BuiltinRun, ::testing::ValuesIn(builtin_names()),
                         [](const ::testing::TestParamInfo<std::string>& scene_info) {
                           return testing::case_name(scene_info.param);
                         });

}  // namespace
}  // namespace clothsim
