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
// RLIMIT_DATA). A scene above it is refused (ResourceError, core/error.h) before anything is
// allocated or written, with a message naming the estimate, its parts and what is available.
// make_simulation() makes the same check with the simulation's part alone (scene/scene_memory.h)
// for callers that step a scene without a run. The running cap on the process's growth
// (RLIMIT_DATA) is process-wide, so it belongs to the command (apps/clothsim/memory_check.h), not
// to the library: the command sets it when the check has passed (RunObserver::memory_checked), as
// a cap set before would hold the check's own message to it (--max-memory 1 left the refusal no
// room to be printed under AddressSanitizer).
#pragma once

#include "run/render_plan.h"
#include "scene/scene.h"
#include "scene/scene_memory.h"
#include "sim/memory_estimate.h"

namespace clothsim {

// The simulation, the output folder of a run (with the scene's exports), its pictures (`plan`)
// and the program.
MemoryEstimate estimate_run_memory(const SceneSpec& spec, const RenderPlan& plan);

}  // namespace clothsim
