// What a simulation will hold, estimated from its shape before anything is allocated.
//
// Every way to start a simulation checks a scene's estimate against the memory that is available
// (core/available_memory.h, memory_limit() and check_memory() below) before it builds the model:
// make_simulation (scene/scene_memory.h), run_scene (run/run_memory.h), the commands. A scene too
// large for the machine is then refused with a message naming the estimate, instead of growing
// until the kernel kills the process (docs/performance.md, "Memory").
//
// The estimate is a sum of named items, each computed by the code that allocates it from the
// element counts of the lattice (model/cloth_model.h, lattice_counts) and the sizes of the real
// element types: ClothModel (lattice_model_bytes), the force scratch (ForceBuffers::bytes_for),
// each integrator's workspace (*::workspace_bytes_for), the event stage (SpringEvents) and the
// collision stage (CollisionStage::bytes_for). So it follows the code: a new array appears in
// the estimate when its owner's bytes_for() counts it, and tests/sim/test_memory_estimate.cpp
// holds the estimate to Simulation::memory_bytes() of built simulations for several sizes and
// every integrator. Only the self-collision candidates depend on the motion; their item is an
// allowance measured on folded sheets (collision/self_contacts.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/available_memory.h"
#include "forces/forces.h"
#include "integrators/integrator.h"
#include "model/cloth_model.h"

namespace clothsim {

struct MemoryItem {
  std::string name;  // "model", "state", "rkf45 workspace", ...
  std::size_t bytes = 0;
};

struct MemoryEstimate {
  std::vector<MemoryItem> items;  // in the order added

  // Adds an item (none for 0 bytes).
  void add(std::string name, std::size_t bytes);
  void add(const MemoryEstimate& other);
  std::size_t total() const;
  // "31.2 GiB (model 9.1 GiB, state 768 MiB, rkf45 workspace 3.0 GiB, ...)".
  std::string describe() const;
};

// What decides a simulation's memory, known before its model is built.
struct SimulationShape {
  LatticeCounts counts;
  std::size_t anchors = 0;
  IntegratorSettings integrator;
  ForceKernel kernel = ForceKernel::automatic;
  Precision precision = Precision::float64;  // of the CPU's forces (ForceOptions::precision)
  // `precision: auto` frame by frame (sim/precision_choice.h): the lattice kernel's arrays in
  // float64 as well, for the windows that need it and for the measurement at each window's start.
  bool precision_by_frame = false;
  // Every connector intact and every spring with its family's values at the start (no cuts):
  // the lattice kernel then keeps no parameter arrays (forces/lattice_kernel.h).
  bool uniform = true;
  // A finite break, yield or crease limit: the event stage's scratch, and the kernel's parameter
  // arrays from the start.
  bool sheet_changes = false;
  bool obstacles = false;       // colliders
  bool self_collision = false;  // collision.self
};

MemoryEstimate estimate_simulation_memory(const SimulationShape& shape);

// The most of the available memory a run may plan to use. The rest is for what no estimate
// counts: other processes' growth while the run goes on, the allocator's own bookkeeping and
// fragmentation, and the page cache of the files the run writes.
inline constexpr double kUsableMemoryFraction = 0.9;

// The bytes a run may plan to use out of `available`.
std::size_t usable_memory(const AvailableMemory& available);

// What a simulation or a run may use, and how to say it in a message.
struct MemoryLimit {
  std::size_t bytes = 0;     // the most the estimate may be
  std::size_t cap = 0;       // the most the process may grow by: all of what was available, or of max_memory
  std::string description;   // "22.8 GiB is available (MemAvailable), of which a run may use 90%, 20.5 GiB"
  std::string source;        // what sets it: the caller's name for max_memory, or AvailableMemory::source
  bool from_caller = false;  // max_memory was given
  bool unknown = false;      // nothing could be read and no max_memory: no check
};

// `max_memory` bytes if given (`source` names it in messages: "--max-memory"), else the usable
// part of the available memory.
MemoryLimit memory_limit(std::optional<std::uint64_t> max_memory, std::string_view source = "--max-memory");

// Throws ResourceError (core/error.h), with the estimate's parts, when `estimate` is above
// `limit`; `what` names what needs it ("the scene", "the case 2000 x 2000 with implicit-euler"),
// `source` what overrides the limit.
void check_memory(const MemoryEstimate& estimate, const MemoryLimit& limit, std::string_view what,
                  std::string_view source = "--max-memory");

// The process's resident memory now (VmRSS), bytes; 0 where it cannot be read. Estimates add it
// as "program": the limits of core/available_memory.h count the whole process.
std::size_t resident_memory();

}  // namespace clothsim
