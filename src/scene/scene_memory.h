// The memory check of a scene's simulation, inside make_simulation() (scene/scene_simulation.h),
// so that every caller is refused alike: the command, the Python module's Simulation, a program
// that embeds the library. The estimate is the simulation's for the scene's shape
// (sim/memory_estimate.h) and the program's resident memory, taken before the model is built;
// above the limit, ResourceError (core/error.h) with the estimate and its parts. A run adds its
// output and pictures (run/run_memory.h) and makes its own check first.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "scene/scene.h"
#include "sim/memory_estimate.h"

namespace clothsim {

// How much memory a caller lets a simulation use.
struct MemoryAllowance {
  std::optional<std::uint64_t> max_memory;  // bytes; unset: 90 % of the memory available
  std::string source = "max_memory";        // what gave max_memory, in messages ("--max-memory")
  // The caller has checked a larger estimate of its own against the same limit (a run, the
  // viewer): no second check, whose resident memory would count what the caller built since.
  bool checked = false;
};

// The shape of the simulation build_model(spec) makes.
SimulationShape simulation_shape(const SceneSpec& spec);

// The simulation of `spec` and the program.
MemoryEstimate estimate_scene_memory(const SceneSpec& spec);

// Throws ResourceError when the scene's simulation will not fit in what `allowance` allows.
void check_scene_memory(const SceneSpec& spec, const MemoryAllowance& allowance);

}  // namespace clothsim
