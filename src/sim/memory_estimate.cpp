#include "sim/memory_estimate.h"

#include <limits>

#include "collision/collision_stage.h"
#include "core/memory_size.h"
#include "events/spring_events.h"
#include "integrators/explicit_runge_kutta.h"
#include "integrators/imex.h"
#include "integrators/implicit_euler.h"
#include "integrators/symplectic_euler.h"
#include "integrators/tableau.h"

namespace clothsim {

void MemoryEstimate::add(std::string name, std::size_t bytes) {
  if (bytes > 0) items.push_back({std::move(name), bytes});
}

void MemoryEstimate::add(const MemoryEstimate& other) {
  for (const MemoryItem& item : other.items) add(item.name, item.bytes);
}

std::size_t MemoryEstimate::total() const {
  std::size_t sum = 0;
  for (const MemoryItem& item : items) sum += item.bytes;
  return sum;
}

std::string MemoryEstimate::describe() const {
  std::string text = format_memory_size(total());
  if (items.empty()) return text;
  text += " (";
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) text += ", ";
    text += items[i].name;
    text += " ";
    text += format_memory_size(items[i].bytes);
  }
  text += ")";
  return text;
}

MemoryEstimate estimate_simulation_memory(const SimulationShape& shape) {
  const LatticeCounts& counts = shape.counts;
  MemoryEstimate estimate;
  estimate.add("model", lattice_model_bytes(counts, shape.anchors));
  estimate.add("state", 2 * counts.particles * sizeof(Vec3));
  const bool parameter_arrays = !shape.uniform || shape.sheet_changes;
  estimate.add("force scratch", ForceBuffers::bytes_for(counts, shape.kernel, parameter_arrays, shape.precision));
  std::size_t workspace = 0;
  switch (shape.integrator.kind) {
    case IntegratorKind::rkf45:
      workspace = ExplicitRungeKutta::workspace_bytes_for(kFehlberg45.stages, counts.particles);
      break;
    case IntegratorKind::rk4:
      workspace = ExplicitRungeKutta::workspace_bytes_for(kClassicRk4.stages, counts.particles);
      break;
    case IntegratorKind::symplectic_euler: workspace = SymplecticEuler::workspace_bytes_for(counts.particles); break;
    case IntegratorKind::implicit_euler:
      workspace = ImplicitEuler::workspace_bytes_for(counts, shape.integrator);
      break;
    case IntegratorKind::imex: workspace = AdditiveRungeKutta::workspace_bytes_for(counts, shape.integrator); break;
  }
  estimate.add(std::string(to_string(shape.integrator.kind)) + " workspace", workspace);
  if (shape.sheet_changes) estimate.add("tearing and plasticity", SpringEvents::bytes_for(counts));
  estimate.add("collisions", CollisionStage::bytes_for(counts, shape.obstacles, shape.self_collision));
  return estimate;
}

std::size_t usable_memory(const AvailableMemory& available) {
  if (!available.known()) return std::numeric_limits<std::size_t>::max();
  return static_cast<std::size_t>(kUsableMemoryFraction * static_cast<double>(available.bytes));
}

}  // namespace clothsim
