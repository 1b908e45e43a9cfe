// From a scene to a running Simulation, in one place: the run command, the viewer, the bench
// suite, the tests and the Python module all start a scene's simulation through make_simulation(),
// so they step the same model from the same state with the same settings, bit for bit.
//
// make_simulation() returns the Simulation by value: it is movable (its model and collision stage,
// which the integrator refers to, are on the heap and move with it), and a caller that keeps it
// behind a pointer (the viewer's reset, a run's result, the Python module's handle) moves it into
// a std::unique_ptr (make_unique_simulation()). Rejected: returning std::unique_ptr<Simulation>,
// which would have turned every caller that keeps its simulation on the stack (most tests, the
// bench) into pointer code for nothing.
//
// The live edits of a running simulation (the viewer's panel and scripts, the Python module's
// Simulation.set) change the scene fields marked live in the parameter registry
// (scene/parameters.h, live_parameter_keys()); apply_live_parameters() turns such an edited scene
// into the Simulation's set_* calls between steps.
#pragma once

#include <memory>

#include "scene/scene.h"
#include "scene/scene_memory.h"
#include "sim/simulation.h"

namespace clothsim {

// The settings of the scene's simulation: its integrator and thread count.
SimulationSettings simulation_settings(const SceneSpec& spec);

// The scene's simulation at its initial state: the memory check (scene/scene_memory.h), then
// build_model(spec), build_initial_state(), simulation_settings(spec). `spec` must be valid
// (validate_scene); throws ResourceError when the simulation will not fit in what `memory`
// allows, before anything is allocated, and InputError when the model cannot be built.
Simulation make_simulation(const SceneSpec& spec, const MemoryAllowance& memory = {});
// The same with `model` instead of build_model(spec): a model built from `spec` and then edited
// (a test adding a collider). The check is made for `spec`.
Simulation make_simulation(const SceneSpec& spec, ClothModel model, const MemoryAllowance& memory = {});
// The same, on the heap.
std::unique_ptr<Simulation> make_unique_simulation(const SceneSpec& spec, const MemoryAllowance& memory = {});
std::unique_ptr<Simulation> make_unique_simulation(const SceneSpec& spec, ClothModel model,
                                                   const MemoryAllowance& memory = {});

// Applies the live fields in which `edited` differs from `current` to `simulation`, whose model
// was built from `current` (with earlier live edits applied). Fields that are not live must be
// equal; `edited` must be valid (validate_scene).
void apply_live_parameters(const SceneSpec& current, const SceneSpec& edited, Simulation& simulation);

}  // namespace clothsim
