// The memory check of a scene's simulation (scene_memory.h).
#include "scene/scene_memory.h"

#include <algorithm>

namespace clothsim {

SimulationShape simulation_shape(const SceneSpec& spec) {
  SimulationShape shape;
  shape.counts = lattice_counts(static_cast<std::size_t>(std::max(spec.lattice.rows, 0)),
                                static_cast<std::size_t>(std::max(spec.lattice.cols, 0)));
  shape.anchors = spec.anchors.size();
  shape.integrator = spec.integrator;
  if (spec.backend.kind == Backend::cpu) {
    // Every scene's sheet is a lattice.
    shape.precision = spec.backend.resolved_precision(spec.integrator, true);
    shape.precision_by_frame = spec.backend.chooses_by_frame(spec.integrator, true);
  }
  // build_model() gives every spring its family's values; only cuts break connectors before the run.
  shape.uniform = spec.cuts.empty();
  shape.sheet_changes = spec.lattice.limits.changes_sheet();
  shape.obstacles = !spec.colliders.empty();
  shape.self_collision = spec.collision.self;
  return shape;
}

MemoryEstimate estimate_scene_memory(const SceneSpec& spec) {
  MemoryEstimate estimate = estimate_simulation_memory(simulation_shape(spec));
  estimate.add("program", resident_memory());
  return estimate;
}

void check_scene_memory(const SceneSpec& spec, const MemoryAllowance& allowance) {
  if (allowance.checked) return;
  check_memory(estimate_scene_memory(spec), memory_limit(allowance.max_memory, allowance.source), "the scene",
               allowance.source);
}

}  // namespace clothsim
