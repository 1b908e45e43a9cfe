#include "sim/memory_estimate.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <string>

#include "collision/collision_stage.h"
#include "core/error.h"
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
  if (shape.precision_by_frame) {
    estimate.add("float64 force scratch", LatticeKernel::array_bytes_for(counts, parameter_arrays, Precision::float64));
  }
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

MemoryLimit memory_limit(std::optional<std::uint64_t> max_memory, std::string_view source) {
  MemoryLimit limit;
  if (max_memory) {
    limit.bytes = static_cast<std::size_t>(*max_memory);
    limit.cap = limit.bytes;
    limit.from_caller = true;
    limit.source = source;
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
  limit.source = available.source;
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
  // A flag takes its value after it ("--max-memory SIZE"); an argument is given a value (max_memory).
  const bool flag = source.rfind("--", 0) == 0;
  if (limit.from_caller) {
    reason += "; use a smaller lattice or a larger " + std::string(source);
  } else {
    reason += "; use a smaller lattice, or " + std::string(source) + (flag ? " SIZE" : "=bytes") + " to override";
  }
  std::vector<ResourceError::Part> parts;
  for (const MemoryItem& item : estimate.items) parts.push_back({item.name, item.bytes});
  throw ResourceError(reason, std::move(parts), estimate.total(), limit.bytes);
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
