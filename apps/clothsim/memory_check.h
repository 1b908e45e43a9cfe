// --max-memory, and the memory check of the commands that build a simulation (run, view, bench).
//
// Before a scene's model is built, its estimated memory (io/run_memory.h, with the pictures of
// run/render_plan.h or the viewer's window) is compared with what the process may use: by default
// kUsableMemoryFraction (90 %) of the memory available (core/available_memory.h: the least of
// MemAvailable, the cgroup limit, RLIMIT_AS and RLIMIT_DATA), or all of --max-memory SIZE when it
// is given. A scene that does not fit is refused as bad input (exit 2) before anything is
// allocated or written, with a message naming the estimate, its parts and what is available
// (docs/cli.md, "Memory"; docs/performance.md, "Memory").
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

#include "run/render_plan.h"
#include "scene/scene.h"
#include "sim/memory_estimate.h"

namespace clothsim::cli {

struct MemoryFlags {
  std::string max_memory;
  CLI::Option* option = nullptr;  // set by add_memory_flag
};

// Registers --max-memory SIZE on `app`.
void add_memory_flag(CLI::App& app, MemoryFlags& flags);

// What a run may use, and how to say it in a message.
struct MemoryLimit {
  std::size_t bytes = 0;    // the most the estimate may be
  std::size_t cap = 0;      // the most the process may grow by (cap_run_growth)
  std::string description;  // "20.5 GiB may be used (90 % of the 22.8 GiB available, MemAvailable)"
  bool from_flag = false;   // --max-memory
  bool unknown = false;     // nothing could be read and no flag: no check
};

// --max-memory if given (InputError naming the flag and the allowed forms if it is not a size),
// else the usable part of the available memory.
MemoryLimit memory_limit(const MemoryFlags& flags);

// Throws InputError when `estimate` is above `limit`; `what` names what needs it ("the scene",
// "the case 2000 x 2000 with implicit-euler").
void check_memory(const MemoryEstimate& estimate, const MemoryLimit& limit, std::string_view what);

// Caps the process's growth (core/available_memory.h, cap_data_growth) at limit.cap: all of the
// memory that was available (the estimate may use 90 % of it), or all of --max-memory. A run that
// outgrows its estimate (self-collision of a sheet folding fast can) then stops with "out of
// memory" instead of being killed by the kernel.
void cap_run_growth(const MemoryLimit& limit);

// `clothsim view`'s check: the scene's simulation, with the parameter arrays a cut needs, and its
// window. Then cap_run_growth. Throws InputError.
void check_view_memory(const SceneSpec& spec, int width, int height, const MemoryFlags& flags);

// `clothsim run`'s check, before its model is built: the scene's run (io/run_memory.h) with its
// pictures (`plan`), then cap_run_growth. Throws InputError.
void check_run_memory(const SceneSpec& spec, const RenderPlan& plan, const MemoryFlags& flags);

}  // namespace clothsim::cli
