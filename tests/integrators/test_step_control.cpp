// The step-size controller of integrators/step_control.inc, the text the CPU's RKF45 and the
// device's rk_control.comp both compile, against its closed forms: a rejection shrinks by
// safety error^(-1/5) within [max_shrink, 1], an acceptance grows by the PI factor
// safety error^(-alpha) previous^beta within [max_shrink, max_growth] (at most 1 after a
// rejection), and clip_step stretches a step that would stop a millionth short of its limit.
// tests/gpu/test_shared_laws.cpp holds the shader's to the same values.
#include "integrators/step_control.h"

#include <gtest/gtest.h>

#include <cmath>

namespace clothsim {
namespace {

using step_control::StepController;

StepController controller(double proposed_step, double previous_error) {
  IntegratorSettings settings;  // safety 0.9, growth 5, shrink 0.1
  StepController c = step_control::make_step_controller(settings);
  c.proposed_step = proposed_step;
  c.previous_error = previous_error;
  return c;
}

TEST(StepControl, ARejectionShrinksByTheOptimalFactor) {
  StepController c = controller(1e-3, 1e-4);
  step_control::reject_step(c, 1e-3, 2.0, false);
  EXPECT_DOUBLE_EQ(c.proposed_step, 1e-3 * 0.9 * std::pow(2.0, -0.2));
  EXPECT_TRUE(c.rejected_before);
  EXPECT_EQ(c.previous_error, 1e-4);  // the I part remembers accepted steps only
  // Never by more than max_shrink; a non-finite error shrinks by max_shrink.
  step_control::reject_step(c, 1e-3, 1e12, false);
  EXPECT_DOUBLE_EQ(c.proposed_step, 1e-4);
  step_control::reject_step(c, 1e-3, 0.0, true);
  EXPECT_DOUBLE_EQ(c.proposed_step, 1e-4);
}

TEST(StepControl, AnAcceptanceTakesThePiFactor) {
  const double alpha = step_control::kControllerAlpha;
  const double beta = step_control::kControllerBeta;
  EXPECT_DOUBLE_EQ(alpha, 0.2 - 0.75 * 0.04);
  StepController c = controller(1e-3, 0.5);
  step_control::accept_step(c, 1e-3, 0.3, false);
  EXPECT_DOUBLE_EQ(c.proposed_step, 1e-3 * 0.9 * std::pow(0.3, -alpha) * std::pow(0.5, beta));
  EXPECT_EQ(c.previous_error, 0.3);
  EXPECT_FALSE(c.rejected_before);
  // Within [max_shrink, max_growth], the error's memory at least 1e-4.
  step_control::accept_step(c, 1e-3, 0.0, false);
  EXPECT_DOUBLE_EQ(c.proposed_step, 5e-3);
  EXPECT_EQ(c.previous_error, 1e-4);
}

TEST(StepControl, NoGrowthAfterARejectionAndClippedStepsKeepTheProposal) {
  StepController c = controller(1e-3, 1e-4);
  c.rejected_before = true;
  step_control::accept_step(c, 1e-3, 1e-6, false);
  EXPECT_EQ(c.proposed_step, 1e-3);  // capped at 1: the step does not grow
  // A step clipped to land on a target keeps the larger of the old proposal and the new one.
  c = controller(1e-2, 1e-4);
  step_control::accept_step(c, 1e-4, 0.9, true);
  EXPECT_EQ(c.proposed_step, 1e-2);
}

TEST(StepControl, ClipStepLandsOnTheLimit) {
  const step_control::ClippedStep free = step_control::clip_step(0.0, 0.1, 1.0);
  EXPECT_FALSE(free.clipped);
  EXPECT_EQ(free.step, 0.1);
  const step_control::ClippedStep shortened = step_control::clip_step(0.5, 0.7, 1.0);
  EXPECT_TRUE(shortened.clipped);
  EXPECT_EQ(shortened.step, 0.5);
  // Within a millionth short of the limit: stretched to end there, not left as a sliver.
  const step_control::ClippedStep stretched = step_control::clip_step(0.0, 1.0 - 1e-7, 1.0);
  EXPECT_TRUE(stretched.clipped);
  EXPECT_EQ(stretched.step, 1.0);
  EXPECT_FALSE(step_control::clip_step(0.0, 1.0 - 1e-5, 1.0).clipped);
}

}  // namespace
}  // namespace clothsim
