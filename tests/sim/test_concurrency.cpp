// Many simulations at once: eight Simulations stepped from eight threads give the same bits as
// the same eight stepped one after another, for RKF45 and implicit Euler, with and without
// self-collision. A Simulation shares nothing with another (no static scratch, no global state in
// the kernels, the integrators or the collision stage), so running them side by side changes
// nothing.
#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

#include "scene/builtin_scenes.h"
#include "scene/scene_simulation.h"

namespace clothsim {
namespace {

struct Case {
  IntegratorKind kind;
  bool self_collision;
};

// Eight variants of a short paper-fig5 run, each its own material, so that a mix-up between
// simulations would show.
SceneSpec variant(const Case& c, int k) {
  SceneSpec spec = builtin_scene("paper-fig5");
  spec.threads = 1;
  spec.integrator.kind = c.kind;
  if (c.kind == IntegratorKind::implicit_euler) spec.integrator.time_step = 1.0 / 240.0;
  spec.lattice.connector.stiffness *= 1.0 + 0.05 * k;
  spec.collision.self = c.self_collision;
  if (c.self_collision) spec.collision.thickness = 0.2;
  return spec;
}

std::vector<Vec3> run_to(const SceneSpec& spec, double time) {
  Simulation simulation = make_simulation(spec);
  EXPECT_TRUE(simulation.advance_to(time));
  std::vector<Vec3> out = simulation.state().position;
  out.insert(out.end(), simulation.state().velocity.begin(), simulation.state().velocity.end());
  return out;
}

class Concurrency : public ::testing::TestWithParam<Case> {};

TEST_P(Concurrency, EightSimulationsOnEightThreadsGiveTheBitsOfEightInARow) {
  constexpr int kSimulations = 8;
  constexpr double kTime = 0.5;
  std::vector<std::vector<Vec3>> alone(kSimulations);
  for (int k = 0; k < kSimulations; ++k) alone[k] = run_to(variant(GetParam(), k), kTime);
  std::vector<std::vector<Vec3>> together(kSimulations);
  {
    std::vector<std::jthread> threads;
    for (int k = 0; k < kSimulations; ++k) {
      threads.emplace_back([&together, k] { together[k] = run_to(variant(GetParam(), k), kTime); });
    }
  }
  for (int k = 0; k < kSimulations; ++k) {
    ASSERT_EQ(alone[k].size(), together[k].size());
    for (std::size_t i = 0; i < alone[k].size(); ++i) {
      ASSERT_EQ(alone[k][i], together[k][i]) << "simulation " << k << ", value " << i;
    }
  }
  // The variants differ: a thread that stepped another's simulation would have been caught.
  EXPECT_NE(alone[0], alone[1]);
}

INSTANTIATE_TEST_SUITE_P(Integrators, Concurrency,
                         ::testing::Values(Case{IntegratorKind::rkf45, false}, Case{IntegratorKind::rkf45, true},
                                           Case{IntegratorKind::implicit_euler, false},
                                           Case{IntegratorKind::implicit_euler, true}),
                         [](const ::testing::TestParamInfo<Case>& param) {
                           return std::string(param.param.kind == IntegratorKind::rkf45 ? "Rkf45" : "ImplicitEuler") +
                                  (param.param.self_collision ? "SelfCollision" : "");
                         });

}  // namespace
}  // namespace clothsim
