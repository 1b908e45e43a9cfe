#include "run/run_memory.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

#include "core/available_memory.h"
#include "core/error.h"
#include "core/memory_size.h"
#include "run/run_writer.h"

namespace clothsim {

MemoryLimit memory_limit(std::optional<std::uint64_t> max_memory, std::string_view source) {
  MemoryLimit limit;
  if (max_memory) {
    limit.bytes = static_cast<std::size_t>(*max_memory);
    limit.cap = limit.bytes;
    limit.from_caller = true;
    limit.description = std::string(source) + " allows " + format_memory_size(*max_memory);
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

void check_memory(const MemoryEstimate& estimate, const MemoryLimit& limit, std::string_view what,
                  std::string_view source) {
  if (limit.unknown || estimate.total() <= limit.bytes) return;
  std::string reason(what);
  reason += " needs an estimated " + estimate.describe() + " and " + limit.description;
  reason += limit.from_caller ? "; use a smaller lattice or a larger " + std::string(source)
                              : "; use a smaller lattice, or " + std::string(source) + " SIZE to override";
  throw InputError("", "", reason);
}

SimulationShape simulation_shape(const SceneSpec& spec) {
  SimulationShape shape;
  shape.counts = lattice_counts(static_cast<std::size_t>(std::max(spec.lattice.rows, 0)),
                                static_cast<std::size_t>(std::max(spec.lattice.cols, 0)));
  shape.anchors = spec.anchors.size();
  shape.integrator = spec.integrator;
  if (spec.backend.kind == Backend::cpu) shape.precision = spec.backend.resolved_precision(spec.integrator);
  // build_model() gives every spring its family's values; only cuts break connectors before the run.
  shape.uniform = spec.cuts.empty();
  shape.sheet_changes = spec.lattice.limits.changes_sheet();
  shape.obstacles = !spec.colliders.empty();
  shape.self_collision = spec.collision.self;
  return shape;
}

MemoryEstimate estimate_run_memory(const SceneSpec& spec, const RenderPlan& plan) {
  const SimulationShape shape = simulation_shape(spec);
  MemoryEstimate estimate = estimate_simulation_memory(shape);
  estimate.add("output buffers", RunWriter::bytes_for(shape.counts, spec.output.exports));
  estimate.add("program", resident_memory());
  estimate.add("pictures", estimate_render_bytes(plan, shape.counts, shape.anchors));
  return estimate;
}

std::size_t resident_memory() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return static_cast<std::size_t>(std::stoull(line.substr(6))) * 1024;
  }
  return 0;
}

}  // namespace clothsim
