// The scene parameters `clothsim view` changes while the simulation runs: the panel's sliders
// and scripted "set" events. They are registry keys (scene/parameters.h), so the panel takes each
// one's range and unit from the registry and a script writes them as `clothsim run --set` does.
//
// Live: the stiffness and damping of the three spring families, gravity, air drag, the particle
// mass and the integrator with its tolerances and steps; Simulation's set_* members apply them
// between steps (sim/simulation.h). Not live: the lattice's shape, rest angles and anchors (they
// define the model's topology or rest state; change them in the scene and restart), the initial
// conditions and the output settings.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "scene/scene.h"
#include "sim/simulation.h"

namespace clothsim::viewer {

std::span<const std::string_view> live_parameter_keys();
bool is_live_parameter(std::string_view key);
// "springs.connector.stiffness, ..., integrator.max_shrink".
std::string live_parameter_list();

// Applies the live fields in which `edited` differs from `current` to `simulation` (whose model
// was built from `current`). Fields that are not live must be equal.
void apply_live_parameters(const SceneSpec& current, const SceneSpec& edited, Simulation& simulation);

}  // namespace clothsim::viewer
