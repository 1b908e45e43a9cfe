// A simulation saved to a checkpoint and restored into a fresh one must go on as the saved one
// does, bit for bit (io/checkpoint.h, Simulation::transfer_state): the check of the CPU's
// checkpoint tests (test_checkpoint.cpp) and of the Vulkan backend's (tests/gpu).
#pragma once

#include <gtest/gtest.h>

#include <filesystem>

#include "io/checkpoint.h"
#include "scene/scene.h"
#include "scene_simulation.h"
#include "sim/simulation.h"
#include "test_checks.h"

namespace clothsim::testing {

// A scene stepped to `split`, saved, and both the saved simulation and one restored into a fresh
// build stepped on to `end`: the two must agree bit for bit in every frame, and in their counters.
// Returns the saved simulation's contact counts at the end.
inline ContactStatistics expect_restored_run_matches(const SceneSpec& spec, double split, double end, int frames) {
  const std::filesystem::path path = checks::fresh_test_folder("restored_run") / "simulation.ckpt";
  Simulation original = testing::one_thread_simulation(spec);
  EXPECT_TRUE(original.advance_to(split));
  write_checkpoint(path, [&](StateArchive& archive) { original.transfer_state(archive); });

  Simulation restored = testing::one_thread_simulation(spec);
  CheckpointReader reader(path);
  restored.transfer_state(reader);
  reader.finish();
  checks::expect_same_bits(restored.state(), original.state());
  for (int k = 1; k <= frames; ++k) {
    const double t = split + (end - split) * k / frames;
    EXPECT_TRUE(original.advance_to(t));
    EXPECT_TRUE(restored.advance_to(t));
    checks::expect_same_bits(restored.state(), original.state());
  }
  EXPECT_EQ(restored.integrator_stats().accepted_steps, original.integrator_stats().accepted_steps);
  EXPECT_EQ(restored.integrator_stats().rejected_steps, original.integrator_stats().rejected_steps);
  EXPECT_EQ(restored.energy_balance().error(), original.energy_balance().error());
  EXPECT_EQ(restored.model_changes().broken_connectors, original.model_changes().broken_connectors);
  EXPECT_EQ(restored.model_changes().max_plastic_strain, original.model_changes().max_plastic_strain);
  EXPECT_EQ(restored.event_totals().breaks, original.event_totals().breaks);
  EXPECT_EQ(restored.contact_statistics().contact_steps, original.contact_statistics().contact_steps);
  EXPECT_EQ(restored.precision_choice().stats().float32_windows, original.precision_choice().stats().float32_windows);
  EXPECT_EQ(restored.precision_choice().stats().float64_windows, original.precision_choice().stats().float64_windows);
  EXPECT_EQ(restored.precision_choice().stats().rest_steps, original.precision_choice().stats().rest_steps);
  return original.contact_statistics();
}

}  // namespace clothsim::testing
