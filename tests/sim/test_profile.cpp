// The run profile by the stages of the step (core/step_profile.h, sim/profile.h): every stage of
// the step is reported in the enum's order, an integrator's parts appear under integration and
// only for the integrator that has them, and the parts and stages add up.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene/scene_simulation.h"
#include "sim/profile.h"

namespace clothsim {
namespace {

std::vector<std::string> names(const std::vector<ProfileRow>& rows) {
  std::vector<std::string> out;
  for (const ProfileRow& row : rows) out.push_back(row.name);
  return out;
}

Simulation short_run(IntegratorKind kind) {
  SceneSpec spec = builtin_scene("paper-fig5");
  spec.lattice.rows = 8;
  spec.lattice.cols = 8;
  spec.anchors.clear();
  spec.integrator.kind = kind;
  spec.integrator.time_step = 1e-4;
  Simulation simulation = make_simulation(spec);
  EXPECT_TRUE(simulation.advance_to(0.02));
  return simulation;
}

TEST(Profile, RowsFollowTheStagesOfTheStep) {
  const Simulation rkf45 = short_run(IntegratorKind::rkf45);
  EXPECT_EQ(names(simulation_profile_rows(rkf45)),
            (std::vector<std::string>{"forces", "integration", "stage sums", "solution and error", "collisions",
                                      "anchors", "events", "checks"}));
  const Simulation rk4 = short_run(IntegratorKind::rk4);
  EXPECT_EQ(names(simulation_profile_rows(rk4)),
            (std::vector<std::string>{"forces", "integration", "stage sums", "solution update", "collisions", "anchors",
                                      "events", "checks"}));
  const Simulation implicit = short_run(IntegratorKind::implicit_euler);
  EXPECT_EQ(names(simulation_profile_rows(implicit)),
            (std::vector<std::string>{"forces", "integration", "jacobians", "assembly", "preconditioner setup",
                                      "linear solve", "collisions", "anchors", "events", "checks"}))
      << "implicit Euler times the parts of its linear system";
}

TEST(Profile, PartsAndStagesAddUp) {
  const Simulation simulation = short_run(IntegratorKind::rkf45);
  const StepProfile profile = simulation.profile();
  EXPECT_GT(profile.seconds(StepStage::forces), 0.0);
  EXPECT_GT(profile.seconds(StepStage::integration), 0.0);
  EXPECT_LE(profile.seconds(StepStage::stage_sums) + profile.seconds(StepStage::solution_and_error),
            profile.seconds(StepStage::integration))
      << "the parts are inside the integration stage";
  const double wall = 10.0;
  const std::vector<ProfileRow> rows = profile_rows(simulation, 0.5, wall);
  double top = 0.0;
  double parts = 0.0;
  double rest = -1.0;
  for (const ProfileRow& row : rows) {
    if (row.name == "total") {
      EXPECT_EQ(row.seconds, wall);
      continue;
    }
    if (row.name == "rest of step") rest = row.seconds;
    (row.depth == 0 ? top : parts) += row.seconds;
  }
  EXPECT_NEAR(top, wall, 1e-9) << "the stages, output and other add up to the total";
  EXPECT_NEAR(parts, profile.seconds(StepStage::integration), 1e-9) << "the parts and the rest of the step";
  EXPECT_GE(rest, 0.0);
  EXPECT_EQ(rows[2].name, "stage sums");
  EXPECT_EQ(rows[4].name, "rest of step") << "right after the parts, before collisions";
}

TEST(Profile, EveryStageHasOneNameAndItsParentIsAStageOfTheStep) {
  for (std::size_t i = 0; i < kStepStages.size(); ++i) {
    EXPECT_EQ(static_cast<std::size_t>(kStepStages[i].stage), i) << "the table is in the enum's order";
    EXPECT_TRUE(is_step_stage(kStepStages[i].parent)) << kStepStages[i].name;
    for (std::size_t j = 0; j < i; ++j) EXPECT_NE(kStepStages[i].name, kStepStages[j].name);
  }
}

}  // namespace
}  // namespace clothsim
