#include "memory_check.h"

#include "core/available_memory.h"
#include "core/error.h"
#include "core/memory_size.h"

namespace clothsim::cli {

void add_memory_flag(CLI::App& app, MemoryFlags& flags) {
  flags.option = app.add_option("--max-memory", flags.max_memory,
                                "the most memory the run may use, e.g. 512M, 8G, 2GiB (K, M, G, T: powers of 1024; "
                                "KB, MB, GB, TB: of 1000); default 90% of the memory available. A scene whose "
                                "estimate is above it is refused (exit 2)")
                     ->type_name("SIZE")
                     ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
}

std::optional<std::uint64_t> max_memory(const MemoryFlags& flags) {
  if (flags.option == nullptr || flags.option->count() == 0) return std::nullopt;
  const std::optional<std::uint64_t> bytes = parse_memory_size(flags.max_memory);
  if (!bytes) {
    std::string reason = "must be ";
    reason += memory_size_forms();
    reason += ", got \"" + flags.max_memory + "\"";
    throw InputError("--max-memory", "", reason);
  }
  return bytes;
}

MemoryLimit memory_limit(const MemoryFlags& flags) { return clothsim::memory_limit(max_memory(flags)); }

void cap_run_growth(const MemoryLimit& limit) {
  if (!limit.unknown) cap_data_growth(limit.cap, limit.source);
}

void check_view_memory(const SceneSpec& spec, int width, int height, const MemoryFlags& flags) {
  const MemoryLimit limit = memory_limit(flags);
  SimulationShape shape = simulation_shape(spec);
  shape.uniform = false;  // the viewer can cut the sheet: the kernel then needs its parameter arrays
  MemoryEstimate estimate = estimate_simulation_memory(shape);
  estimate.add("program", resident_memory());
  estimate.add("window", picture_bytes(width, height, 4, shape.counts));
  check_memory(estimate, limit, "the scene");
  cap_run_growth(limit);
}

}  // namespace clothsim::cli
