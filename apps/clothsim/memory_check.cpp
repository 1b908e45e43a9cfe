#include "memory_check.h"

#include <algorithm>
#include <cmath>

#include "core/available_memory.h"
#include "core/error.h"
#include "core/memory_size.h"
#include "io/run_memory.h"

namespace clothsim::cli {

void add_memory_flag(CLI::App& app, MemoryFlags& flags) {
  flags.option = app.add_option("--max-memory", flags.max_memory,
                                "the most memory the run may use, e.g. 512M, 8G, 2GiB (K, M, G, T: powers of 1024; "
                                "KB, MB, GB, TB: of 1000); default 90% of the memory available. A scene whose "
                                "estimate is above it is refused (exit 2)")
                     ->type_name("SIZE")
                     ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
}

MemoryLimit memory_limit(const MemoryFlags& flags) {
  MemoryLimit limit;
  if (flags.option != nullptr && flags.option->count() > 0) {
    const std::optional<std::uint64_t> bytes = parse_memory_size(flags.max_memory);
    if (!bytes) {
      std::string reason = "must be ";
      reason += memory_size_forms();
      reason += ", got \"" + flags.max_memory + "\"";
      throw InputError("--max-memory", "", reason);
    }
    limit.bytes = static_cast<std::size_t>(*bytes);
    limit.cap = limit.bytes;
    limit.from_flag = true;
    limit.description = "--max-memory allows " + format_memory_size(*bytes);
    return limit;
  }
  const AvailableMemory available = available_memory();
  if (!available.known()) {
    limit.unknown = true;
    return limit;
  }
  limit.bytes = usable_memory(available);
  limit.cap = available.bytes;
  const auto percent = static_cast<int>(std::lround(100.0 * kUsableMemoryFraction));
  limit.description = format_memory_size(available.bytes) + " is available (" + available.source +
                      "), of which a run " + "may use " + std::to_string(percent) + "%, " +
                      format_memory_size(limit.bytes);
  return limit;
}

void check_memory(const MemoryEstimate& estimate, const MemoryLimit& limit, std::string_view what) {
  if (limit.unknown || estimate.total() <= limit.bytes) return;
  std::string reason(what);
  reason += " needs an estimated " + estimate.describe() + " and " + limit.description;
  reason += limit.from_flag ? "; use a smaller lattice or a larger --max-memory"
                            : "; use a smaller lattice, or --max-memory SIZE to override";
  throw InputError("", "", reason);
}

void cap_run_growth(const MemoryLimit& limit) {
  if (!limit.unknown) cap_data_growth(limit.cap);
}

void check_run_memory(const SceneSpec& spec, const RenderPlan& plan, const MemoryFlags& flags) {
  const MemoryLimit limit = memory_limit(flags);
  MemoryEstimate estimate = estimate_run_memory(spec);
  const SimulationShape shape = simulation_shape(spec);
  estimate.add("pictures", estimate_render_bytes(plan, shape.counts, shape.anchors));
  check_memory(estimate, limit, "the scene");
  cap_run_growth(limit);
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
