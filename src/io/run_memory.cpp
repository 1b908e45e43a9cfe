#include "io/run_memory.h"

#include <algorithm>
#include <fstream>
#include <string>

#include "io/run_writer.h"

namespace clothsim {

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

MemoryEstimate estimate_run_memory(const SceneSpec& spec) {
  const SimulationShape shape = simulation_shape(spec);
  MemoryEstimate estimate = estimate_simulation_memory(shape);
  estimate.add("output buffers", RunWriter::bytes_for(shape.counts, spec.output.exports));
  estimate.add("program", resident_memory());
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
