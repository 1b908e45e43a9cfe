// Real-time pacing readouts (apps/clothsim/viewer/frame_pacer.h): frames per second and simulated
// time per wall time over the last second, and the "behind real time" sign.
#include <gtest/gtest.h>

#include "viewer/frame_pacer.h"

namespace clothsim::viewer {
namespace {

TEST(FramePacer, ALongFrameAsksForAtMostATenthOfASecond) {
  EXPECT_EQ(FramePacer::simulated_step(1.0 / 60.0), 1.0 / 60.0);
  EXPECT_EQ(FramePacer::simulated_step(3.0), FramePacer::kLongestFrame);
  EXPECT_EQ(FramePacer::simulated_step(-1.0), 0.0);
}

TEST(FramePacer, KeepingUpReadsOneAndFallingBehindIsFlagged) {
  FramePacer keeping_up;
  for (int i = 0; i < 120; ++i) keeping_up.record(1.0 / 60.0, 1.0 / 60.0, true);
  EXPECT_NEAR(keeping_up.frames_per_second(), 60.0, 1.5);
  EXPECT_NEAR(keeping_up.real_time_ratio(), 1.0, 1e-12);
  EXPECT_FALSE(keeping_up.behind());

  FramePacer slow;  // 20 fps, simulating 40% of each frame's wall time
  for (int i = 0; i < 60; ++i) slow.record(0.05, 0.02, true);
  EXPECT_NEAR(slow.frames_per_second(), 20.0, 1.5);
  EXPECT_NEAR(slow.real_time_ratio(), 0.4, 1e-12);
  EXPECT_TRUE(slow.behind());
}

TEST(FramePacer, PausedFramesDoNotCountAsBehind) {
  FramePacer pacer;
  for (int i = 0; i < 120; ++i) pacer.record(1.0 / 60.0, 0.0, false);
  EXPECT_EQ(pacer.real_time_ratio(), 0.0);
  EXPECT_FALSE(pacer.behind());
  // Old frames leave the one-second window: after a second of playing in real time the ratio is 1.
  for (int i = 0; i < 70; ++i) pacer.record(1.0 / 60.0, 1.0 / 60.0, true);
  EXPECT_NEAR(pacer.real_time_ratio(), 1.0, 1e-12);
  EXPECT_FALSE(pacer.behind());
}

}  // namespace
}  // namespace clothsim::viewer
