// The built-in `tear-crumple` run on its scene's backend and checked for what it exists to show:
// the paper's three goals and self-collision together. It tears (connectors break beyond the
// notch cut before the run), it creases (radial springs' rest angles moved for good), it folds onto
// itself (self-contacts), and the brute-force check (sheet_crossings.h) finds no crossing at any
// frame. Shared by the CPU's test (test_self_crossings.cpp) and the Vulkan backend's (tests/gpu).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <numbers>

#include "scene/scene.h"
#include "scene/scene_model.h"
#include "scene_simulation.h"
#include "sheet_crossings.h"
#include "sim/simulation.h"

namespace clothsim::testing {

// Runs `spec` (tear-crumple, possibly shortened) to `end` in `checks` frames and expects it to tear,
// crease and touch itself, and never to cross itself.
inline void expect_tear_crumple_run(const SceneSpec& spec, double end, int checks) {
  const ClothModel built = build_model(spec);
  Simulation simulation = one_thread_simulation(spec);
  const std::size_t notch = simulation.model_changes().broken_connectors;  // cut before the run
  ASSERT_GT(notch, 0u);
  for (int check = 1; check <= checks; ++check) {
    ASSERT_TRUE(simulation.advance_to(end * check / checks)) << simulation.failure()->message;
    EXPECT_EQ(count_sheet_crossings(simulation.model(), simulation.state().position), 0u)
        << "frame " << check << " of " << checks;
  }
  // It tears on from the notch.
  EXPECT_GE(simulation.model_changes().broken_connectors, notch + 5);
  // It creases: rest angles moved past the 20 degrees the material keeps, in many springs.
  const ClothModel& model = simulation.model();
  std::size_t creased = 0;
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    if (model.radial_live[r] == 0) continue;
    if (std::abs(model.radial_rest_angle[r] - built.radial_rest_angle[r]) > 10.0 / 180.0 * std::numbers::pi) {
      ++creased;
    }
  }
  EXPECT_GE(creased, 20u);
  EXPECT_GT(simulation.model_changes().max_plastic_strain, 0.0) << "it yields";
  // It folds onto itself.
  EXPECT_GT(simulation.contact_statistics().self_contact_steps, 100u);
}

}  // namespace clothsim::testing
