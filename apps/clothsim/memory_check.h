// --max-memory, and the command's part of the memory check (run/run_memory.h has the rest).
//
// The library refuses a scene too large for the memory before anything is allocated or written
// (run_scene, and here `view` and `bench` with their own estimates): by default above 90 % of the
// memory available, or above --max-memory SIZE when it is given (docs/cli.md, "Memory";
// docs/performance.md, "Memory"). What only the command does is cap the process's growth, since
// that limit (RLIMIT_DATA) holds for the whole process: a run that outgrows its estimate
// (self-collision of a sheet folding fast can) then stops with "out of memory" instead of being
// killed by the kernel.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "run/run_memory.h"
#include "scene/scene.h"

namespace clothsim::cli {

struct MemoryFlags {
  std::string max_memory;
  CLI::Option* option = nullptr;  // set by add_memory_flag
};

// Registers --max-memory SIZE on `app`.
void add_memory_flag(CLI::App& app, MemoryFlags& flags);

// --max-memory in bytes if given (InputError naming the flag and the allowed forms if it is not
// a size).
std::optional<std::uint64_t> max_memory(const MemoryFlags& flags);

// What the command may use: --max-memory if given, else the usable part of the available memory.
MemoryLimit memory_limit(const MemoryFlags& flags);

// Caps the process's growth (core/available_memory.h, cap_data_growth) at limit.cap: all of the
// memory that was available (the estimate may use 90 % of it), or all of --max-memory.
void cap_run_growth(const MemoryLimit& limit);

// `clothsim view`'s check: the scene's simulation, with the parameter arrays a cut needs, and its
// window. Then cap_run_growth. Throws InputError.
void check_view_memory(const SceneSpec& spec, int width, int height, const MemoryFlags& flags);

}  // namespace clothsim::cli
