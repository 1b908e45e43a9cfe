// The memory check of a run: what a run of a scene needs, estimated from the scene alone before
// anything is built, against what the process may use. run_scene() and resume_run() make it
// before the model is built, so every caller (the command, the Python module, a program that
// embeds the library) is refused alike; `clothsim view` and `clothsim bench` make it with their
// own estimates (docs/performance.md, "Memory").
//
// The estimate: the simulation (sim/memory_estimate.h) for the scene's shape, the output folder's
// buffers (RunWriter::bytes_for), the pictures (run/render_plan.h) and the program itself, the
// resident memory of the process so far (code, libraries, the scene), measured. The limit: all of
// max_memory when it is given, else kUsableMemoryFraction (90 %) of the memory available
// (core/available_memory.h: the least of MemAvailable, the cgroup limit, RLIMIT_AS and
// RLIMIT_DATA). A scene above it is refused as bad input before anything is allocated or written,
// with a message naming the estimate, its parts and what is available. The running cap on the
// process's growth (RLIMIT_DATA) is process-wide, so it belongs to the command
// (apps/clothsim/memory_check.h), not to the library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "run/render_plan.h"
#include "scene/scene.h"
#include "sim/memory_estimate.h"

namespace clothsim {

// What a run may use, and how to say it in a message.
struct MemoryLimit {
  std::size_t bytes = 0;     // the most the estimate may be
  std::size_t cap = 0;       // the most the process may grow by: all of what was available, or of max_memory
  std::string description;   // "20.5 GiB may be used (90 % of the 22.8 GiB available, MemAvailable)"
  bool from_caller = false;  // max_memory was given
  bool unknown = false;      // nothing could be read and no max_memory: no check
};

// `max_memory` bytes if given (`source` names it in messages: "--max-memory"), else the usable
// part of the available memory.
MemoryLimit memory_limit(std::optional<std::uint64_t> max_memory, std::string_view source = "--max-memory");

// Throws InputError when `estimate` is above `limit`; `what` names what needs it ("the scene",
// "the case 2000 x 2000 with implicit-euler"), `source` what overrides the limit.
void check_memory(const MemoryEstimate& estimate, const MemoryLimit& limit, std::string_view what,
                  std::string_view source = "--max-memory");

// The shape of the simulation build_model(spec) makes.
SimulationShape simulation_shape(const SceneSpec& spec);

// The simulation, the output folder of a run (with the scene's exports), its pictures (`plan`)
// and the program.
MemoryEstimate estimate_run_memory(const SceneSpec& spec, const RenderPlan& plan);

// The process's resident memory now (VmRSS), bytes; 0 where it cannot be read.
std::size_t resident_memory();

}  // namespace clothsim
