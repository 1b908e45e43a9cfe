// The memory estimate (sim/memory_estimate.h) against what built simulations hold: for several
// lattice sizes and every integrator, each item of the estimate equals the bytes of the part it
// stands for (Simulation::memory_bytes() and its pieces), so the estimate follows the code; the
// event stage after a first step of a sheet that can tear; the collision stage within its
// allowance; and the description's form.
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "core/memory_size.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene/scene_memory.h"
#include "scene/scene_simulation.h"
#include "scene_simulation.h"
#include "sim/memory_estimate.h"
#include "sim/simulation.h"
#include "test_checks.h"

namespace clothsim {
namespace {

using checks::contains;

SceneSpec paper_sheet(int rows, int cols, IntegratorKind kind) {
  SceneSpec spec =
      scene_from_paper_args(std::to_string(rows) + "," + std::to_string(cols) + ",1,4,1,1400,200,80,5,1", "test");
  spec.integrator.kind = kind;
  spec.integrator.time_step = 1e-4;
  return spec;
}

SimulationShape shape_of(const SceneSpec& spec) {
  SimulationShape shape;
  shape.counts =
      lattice_counts(static_cast<std::size_t>(spec.lattice.rows), static_cast<std::size_t>(spec.lattice.cols));
  shape.anchors = spec.anchors.size();
  shape.integrator = spec.integrator;
  // On `auto` (the CPU's default), RKF45 holds float32 forces with the float64 arrays beside them.
  shape.precision = spec.backend.resolved_precision(spec.integrator, true);
  shape.precision_by_frame = spec.backend.chooses_by_frame(spec.integrator, true);
  shape.uniform = spec.cuts.empty();
  shape.sheet_changes = spec.lattice.limits.changes_sheet();
  shape.obstacles = !spec.colliders.empty();
  shape.self_collision = spec.collision.self;
  return shape;
}

std::size_t item(const MemoryEstimate& estimate, const std::string& name) {
  for (const MemoryItem& entry : estimate.items) {
    if (entry.name == name) return entry.bytes;
  }
  return 0;
}

TEST(LatticeCounts, CountWhatBuildLatticeMakes) {
  for (const auto& [rows, cols] : std::vector<std::pair<int, int>>{{1, 2}, {2, 1}, {1, 7}, {2, 2}, {3, 5}, {17, 23}}) {
    LatticeDef def;
    def.rows = rows;
    def.cols = cols;
    const ClothModel model = build_lattice(def, Environment{}, {});
    const LatticeCounts counts = lattice_counts(static_cast<std::size_t>(rows), static_cast<std::size_t>(cols));
    EXPECT_EQ(counts.particles, model.particle_count()) << rows << " x " << cols;
    EXPECT_EQ(counts.connectors, model.connector_count()) << rows << " x " << cols;
    EXPECT_EQ(counts.radials, model.radial_count()) << rows << " x " << cols;
    EXPECT_EQ(lattice_model_bytes(counts, 0), model.bytes()) << rows << " x " << cols;
  }
}

// Every item but the collision stage's is exact: the model, the state, the force scratch and
// the integrator's workspace are what Simulation::memory_bytes() counts, to the byte.
TEST(MemoryEstimate, EqualsTheBytesOfBuiltSimulationsForEveryIntegrator) {
  for (const auto& [rows, cols] : std::vector<std::pair<int, int>>{{5, 5}, {17, 23}, {64, 64}, {101, 37}}) {
    for (IntegratorKind kind : all_integrator_kinds()) {
      const SceneSpec spec = paper_sheet(rows, cols, kind);
      const MemoryEstimate estimate = estimate_simulation_memory(shape_of(spec));
      Simulation simulation = testing::one_thread_simulation(spec);
      const std::string where =
          std::to_string(rows) + " x " + std::to_string(cols) + " " + std::string(to_string(kind));
      EXPECT_EQ(item(estimate, "model"), simulation.model().bytes()) << where;
      EXPECT_EQ(estimate.total(), simulation.memory_bytes()) << where << ": " << estimate.describe();
      ASSERT_TRUE(simulation.advance_to(1e-3)) << where;
      EXPECT_EQ(estimate.total(), simulation.memory_bytes()) << where << " after a step";
    }
  }
}

// A sheet that can tear holds the kernel's parameter arrays from the start and, after its first
// step, the event stage's scratch; a sheet cut before the run holds the arrays too.
TEST(MemoryEstimate, CountsTheArraysOfSheetsThatChange) {
  SceneSpec tearing = paper_sheet(24, 31, IntegratorKind::rkf45);
  tearing.lattice.limits.break_strain = 0.5;
  SimulationShape shape = shape_of(tearing);
  ASSERT_TRUE(shape.sheet_changes);
  Simulation simulation = testing::one_thread_simulation(tearing);
  ASSERT_TRUE(simulation.advance_to(1e-3));
  const MemoryEstimate estimate = estimate_simulation_memory(shape);
  EXPECT_GT(item(estimate, "tearing and plasticity"), 0u);
  EXPECT_EQ(estimate.total(), simulation.memory_bytes()) << estimate.describe();

  SimulationShape uniform = shape;
  uniform.sheet_changes = false;
  SimulationShape cut = uniform;
  cut.uniform = false;
  // The 26 parameter arrays of the lattice kernel, a float and a double per particle each (and
  // padding): RKF45 on `auto`, the default, holds the float32 and the float64 arrays.
  const auto force_scratch = [&](const SimulationShape& of) {
    const MemoryEstimate of_shape = estimate_simulation_memory(of);
    return item(of_shape, "force scratch") + item(of_shape, "float64 force scratch");
  };
  EXPECT_GE(force_scratch(cut) - force_scratch(uniform),
            26 * (sizeof(float) + sizeof(double)) * shape.counts.particles);
}

// The collision stage holds what depends on the sheet's motion (candidate pairs, grid entries):
// its item is an allowance. A sheet falling onto itself with self-collision stays within it.
TEST(MemoryEstimate, CollisionStageStaysWithinItsAllowanceOnAFlatSheet) {
  SceneSpec spec = paper_sheet(48, 48, IntegratorKind::rkf45);
  spec.collision.self = true;
  spec.collision.thickness = 0.05;
  const MemoryEstimate estimate = estimate_simulation_memory(shape_of(spec));
  Simulation simulation = testing::one_thread_simulation(spec);
  ASSERT_TRUE(simulation.advance_to(0.05));
  EXPECT_GT(item(estimate, "collisions"), 0u);
  EXPECT_LE(simulation.memory_bytes(), estimate.total()) << estimate.describe();
  EXPECT_GT(simulation.memory_bytes(), estimate.total() / 2) << estimate.describe();
}

// A sheet on obstacles holds the obstacle stage's arrays: the estimate counts them from the
// scene's colliders (scene/scene_memory.h: simulation_shape) and bounds what the run holds once
// the sheet lies on the table, closely.
TEST(MemoryEstimate, CountsTheObstacleStageOfASheetOnATable) {
  SceneSpec spec = builtin_scene("tablecloth");
  spec.threads = 1;
  ASSERT_FALSE(spec.colliders.empty());
  const SimulationShape shape = simulation_shape(spec);
  ASSERT_TRUE(shape.obstacles);
  SimulationShape bare = shape;
  bare.obstacles = false;
  const MemoryEstimate estimate = estimate_simulation_memory(shape);
  // Each particle's resolved position, velocity change, penetration and flag at least.
  EXPECT_GE(item(estimate, "collisions") - item(estimate_simulation_memory(bare), "collisions"),
            shape.counts.particles * (2 * sizeof(Vec3) + sizeof(double) + sizeof(std::uint8_t)));
  Simulation simulation = make_simulation(spec);
  ASSERT_TRUE(simulation.advance_to(0.3));  // on the table by now
  ASSERT_GT(simulation.contact_statistics().contacts, 0u);
  EXPECT_LE(simulation.memory_bytes(), estimate.total()) << estimate.describe();
  EXPECT_GT(simulation.memory_bytes(), estimate.total() * 9 / 10) << estimate.describe();
}

TEST(MemoryEstimate, DescribesTheTotalAndEachItem) {
  MemoryEstimate estimate;
  estimate.add("model", std::size_t{3} << 30);
  estimate.add("state", std::size_t{512} << 20);
  estimate.add("nothing", 0);
  EXPECT_EQ(estimate.items.size(), 2u);
  EXPECT_EQ(estimate.describe(), "3.50 GiB (model 3.00 GiB, state 512 MiB)");
}

TEST(MemoryEstimate, ARunMayUseNinetyPercentOfWhatIsAvailable) {
  const AvailableMemory available{std::size_t{10} << 30, "MemAvailable"};
  EXPECT_EQ(usable_memory(available), static_cast<std::size_t>(0.9 * static_cast<double>(std::size_t{10} << 30)));
  EXPECT_EQ(usable_memory(AvailableMemory{}), std::numeric_limits<std::size_t>::max());
}

}  // namespace
}  // namespace clothsim
