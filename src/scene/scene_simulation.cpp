// A scene's simulation, and the live edits of one (scene_simulation.h).
#include "scene/scene_simulation.h"

#include <type_traits>
#include <utility>

#include "scene/scene_model.h"

namespace clothsim {

static_assert(std::is_nothrow_move_constructible_v<Simulation>, "make_simulation() returns a Simulation by value");

SimulationSettings simulation_settings(const SceneSpec& spec) {
  SimulationSettings settings;
  settings.integrator = scene_integrator(spec);
  settings.threads = spec.threads;
  settings.backend = spec.backend;
  return settings;
}

Simulation make_simulation(const SceneSpec& spec, const MemoryAllowance& memory) {
  check_scene_memory(spec, memory);
  MemoryAllowance checked = memory;
  checked.checked = true;
  return make_simulation(spec, build_model(spec), checked);
}

Simulation make_simulation(const SceneSpec& spec, ClothModel model, const MemoryAllowance& memory) {
  check_scene_memory(spec, memory);
  ClothState initial = build_initial_state(model, spec);
  return Simulation(std::move(model), std::move(initial), simulation_settings(spec));
}

std::unique_ptr<Simulation> make_unique_simulation(const SceneSpec& spec, const MemoryAllowance& memory) {
  return std::make_unique<Simulation>(make_simulation(spec, memory));
}

std::unique_ptr<Simulation> make_unique_simulation(const SceneSpec& spec, ClothModel model,
                                                   const MemoryAllowance& memory) {
  return std::make_unique<Simulation>(make_simulation(spec, std::move(model), memory));
}

namespace {

bool same(const SpringParameters& a, const SpringParameters& b) {
  return a.stiffness == b.stiffness && a.damping == b.damping;
}

bool same(const IntegratorSettings& a, const IntegratorSettings& b) {
  return a.kind == b.kind && a.relative_tolerance == b.relative_tolerance &&
         a.absolute_tolerance == b.absolute_tolerance && a.time_step == b.time_step && a.min_step == b.min_step &&
         a.max_step == b.max_step && a.safety == b.safety && a.max_growth == b.max_growth &&
         a.max_shrink == b.max_shrink;
}

}  // namespace

void apply_live_parameters(const SceneSpec& current, const SceneSpec& edited, Simulation& simulation) {
  const LatticeDef& was = current.lattice;
  const LatticeDef& now = edited.lattice;
  if (!same(was.connector, now.connector)) simulation.set_spring_parameters(SpringFamily::connector, now.connector);
  if (!same(was.adjacent, now.adjacent)) simulation.set_spring_parameters(SpringFamily::adjacent, now.adjacent);
  if (!same(was.opposite, now.opposite)) simulation.set_spring_parameters(SpringFamily::opposite, now.opposite);
  if (was.particle_mass != now.particle_mass) simulation.set_particle_mass(now.particle_mass);
  if (!(current.environment.gravity == edited.environment.gravity) ||
      current.environment.air_drag != edited.environment.air_drag) {
    simulation.set_environment(edited.environment);
  }
  const IntegratorSettings integrator = scene_integrator(edited);
  if (!same(scene_integrator(current), integrator)) simulation.set_integrator(integrator);
}

}  // namespace clothsim
