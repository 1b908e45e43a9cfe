// The memory check inside make_simulation() (scene/scene_memory.h): a scene too large for the
// memory the process may use is refused by every way of starting its simulation, at once, before
// its model is built, with the estimate and its parts in the error; max_memory moves the limit.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "core/error.h"
#include "scene/builtin_scenes.h"
#include "scene/scene_memory.h"
#include "scene/scene_simulation.h"

namespace clothsim {
namespace {

// 4096 x 4096 with implicit Euler: tens of GiB (about 77), more than any test machine has free.
SceneSpec huge_scene() {
  SceneSpec spec = builtin_scene("paper-fig5");
  spec.lattice.rows = 4096;
  spec.lattice.cols = 4096;
  spec.anchors.clear();
  spec.integrator.kind = IntegratorKind::implicit_euler;
  return spec;
}

template <typename Start>
ResourceError refusal(Start start) {
  const auto begin = std::chrono::steady_clock::now();
  try {
    start();
  } catch (const ResourceError& error) {
    // Refused from the shape alone: building the model would take far longer than this.
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count(), 2.0);
    return error;
  }
  ADD_FAILURE() << "not refused";
  return ResourceError("", {}, 0, 0);
}

TEST(SceneMemory, AHugeSceneIsRefusedByEveryWayToStartItsSimulation) {
  const SceneSpec spec = huge_scene();
  const MemoryEstimate estimate = estimate_scene_memory(spec);
  for (const ResourceError& error :
       {refusal([&] { make_simulation(spec); }), refusal([&] { make_unique_simulation(spec); })}) {
    // The same estimate but for the program's resident memory, measured at each call.
    EXPECT_NEAR(static_cast<double>(error.estimate_bytes()), static_cast<double>(estimate.total()), 64e6);
    EXPECT_GT(error.estimate_bytes(), error.limit_bytes());
    ASSERT_EQ(error.parts().size(), estimate.items.size());
    EXPECT_EQ(error.parts().front().name, "model");
    const std::string message = error.what();
    EXPECT_NE(message.find("the scene needs an estimated"), std::string::npos) << message;
    EXPECT_NE(message.find("implicit-euler workspace"), std::string::npos) << message;
    EXPECT_NE(message.find("max_memory=bytes to override"), std::string::npos) << message;
  }
}

TEST(SceneMemory, MaxMemoryRefusesASmallSceneAndLetsItThroughWhenLarger) {
  SceneSpec spec = builtin_scene("paper-fig5");
  const std::size_t needed = estimate_scene_memory(spec).total();
  const ResourceError error = refusal([&] { make_simulation(spec, MemoryAllowance{needed / 2, "limit", false}); });
  EXPECT_EQ(error.limit_bytes(), needed / 2);
  EXPECT_NE(std::string(error.what()).find("limit allows"), std::string::npos) << error.what();
  EXPECT_NE(std::string(error.what()).find("or a larger limit"), std::string::npos) << error.what();
  // Twice the estimate, less what the program grew by since: room enough.
  const Simulation simulation = make_simulation(spec, MemoryAllowance{2 * needed, "limit", false});
  EXPECT_EQ(simulation.model().particle_count(), std::size_t(spec.lattice.rows) * std::size_t(spec.lattice.cols));
  // A caller that checked already (a run, the viewer) is not checked again.
  EXPECT_NO_THROW(make_simulation(spec, MemoryAllowance{1, "limit", true}));
}

}  // namespace
}  // namespace clothsim
