// The setup tests share to run a scene: the library's make_simulation (scene/scene_simulation.h)
// on one thread, so that figures do not depend on the machine's load.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "scene/scene.h"
#include "scene/scene_model.h"
#include "scene/scene_simulation.h"
#include "sim/backend.h"
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

// The BackendError a scene's simulation is refused with, or "no refusal".
inline std::string refusal_of(const SceneSpec& spec) {
  try {
    Simulation simulation = make_simulation(spec);
  } catch (const BackendError& error) {
    return std::string(error.what());
  }
  return "no refusal";
}

// Where a run ended: the state, the energy balance and the integrator's statistics; the sheet's
// events, the model's spring arrays the laws change and the work they released; the obstacles'
// contacts.
struct RunEnd {
  std::vector<Vec3> position, velocity;
  double balance_error = 0.0;
  double energy_scale = 0.0;
  IntegratorStats stats;
  SpringEventCounts events;
  ModelChanges changes;
  std::vector<std::uint8_t> live;                           // the connectors'
  std::vector<double> break_time, rest_length, rest_angle;  // the connectors', the radial springs'
  double fracture_work = 0.0, plastic_work = 0.0;           // J
  std::uint64_t contact_steps = 0;  // particles in contact with an obstacle, summed over the steps
};

// Where `simulation` stands now.
inline RunEnd run_end(const Simulation& simulation) {
  const ClothState& state = simulation.state();
  const ClothModel& model = simulation.model();
  return {state.position,
          state.velocity,
          simulation.energy_balance().error(),
          simulation.energy_scale(),
          simulation.integrator_stats(),
          simulation.event_totals(),
          simulation.model_changes(),
          model.connector_live,
          model.connector_break_time,
          model.connector_rest_length,
          model.radial_rest_angle,
          state.fracture_work,
          state.plastic_work,
          simulation.contact_statistics().contact_steps};
}

// Runs `spec` (on its own thread count) frame by frame to `t`, expecting every frame to succeed.
inline RunEnd run_scene_to(const SceneSpec& spec, double t) {
  Simulation simulation = make_simulation(spec);
  const int frames = static_cast<int>(std::lround(t * spec.output.fps));
  for (int k = 1; k <= frames; ++k) {
    EXPECT_TRUE(simulation.advance_to(static_cast<double>(k) / spec.output.fps))
        << spec.name << ": " << simulation.failure()->message;
  }
  return run_end(simulation);
}

// The largest |a_p - b_p| over the particles.
inline double largest_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double largest = 0.0;
  for (std::size_t p = 0; p < a.size(); ++p) largest = std::max(largest, norm(a[p] - b[p]));
  return largest;
}

}  // namespace clothsim::testing
