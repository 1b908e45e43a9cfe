#include "run/run_memory.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

#include "core/available_memory.h"
#include "core/error.h"
#include "core/memory_size.h"
#include "run/run_scene.h"
#include "run/run_writer.h"

namespace clothsim {

MemoryEstimate estimate_run_memory(const SceneSpec& spec, const RenderPlan& plan) {
  const SimulationShape shape = simulation_shape(spec);
  MemoryEstimate estimate = estimate_simulation_memory(shape);
  estimate.add("output buffers", RunWriter::bytes_for(shape.counts, last_frame(spec.output) + 1, spec.output.exports));
  estimate.add("program", resident_memory());
  // The model changes during the run when its springs have laws or an anchor lets go.
  const bool model_changes =
      shape.sheet_changes || std::any_of(spec.anchors.begin(), spec.anchors.end(), [](const AnchorSpec& anchor) {
        return std::isfinite(anchor.release_time);
      });
  estimate.add("pictures", estimate_render_bytes(plan, shape.counts, shape.anchors, model_changes));
  return estimate;
}

}  // namespace clothsim
