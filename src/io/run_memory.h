// What a run of a scene needs in memory, estimated from the scene alone before anything is
// built: the simulation (sim/memory_estimate.h) for the scene's shape, the output folder's
// buffers (RunWriter::bytes_for) and the program itself. The tools add what they draw
// (apps/clothsim) and check the sum against the memory available (docs/performance.md, "Memory").
#pragma once

#include <cstddef>

#include "scene/scene.h"
#include "sim/memory_estimate.h"

namespace clothsim {

// The shape of the simulation build_model(spec) makes.
SimulationShape simulation_shape(const SceneSpec& spec);

// The simulation, the output folder of `clothsim run` (with the scene's exports), and the
// program: the resident memory of the process so far (code, libraries, the scene), measured.
MemoryEstimate estimate_run_memory(const SceneSpec& spec);

// The process's resident memory now (VmRSS), bytes; 0 where it cannot be read.
std::size_t resident_memory();

}  // namespace clothsim
