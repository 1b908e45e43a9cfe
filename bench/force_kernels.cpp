// Micro-benchmarks of one force evaluation: the general element-list path and the structured
// lattice kernel, on square sheets of the paper's material bent into a wave (no singular
// springs) and flat (every opposite spring singular: *Flat), for 1 and 2 threads. Counters: ns per particle and force
// evaluations per second. *Torn: the issue-7 target case, the wavy sheet with 10 % of its
// connectors broken (a fixed random choice) and every spring's rest value different, as a torn,
// stretched and creased sheet has them; it must stay within 1.3 times Lattice. *Float32: the
// lattice kernel's springs in float (forces/lattice_kernel.h, "Precision").
//
//   build/bench/bench/clothsim_microbench --benchmark_filter=Lattice --benchmark_repetitions=5
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "core/precision.h"
#include "forces/forces.h"
#include "model/model_edits.h"

namespace clothsim {
namespace {

struct Sheet {
  ClothModel model;
  std::vector<Vec3> position;
  std::vector<Vec3> velocity;
};

// A wavy sheet (no singular springs), or a flat one falling with a velocity field that bends it
// (every opposite spring exactly straight: the singular path, as at the start of most runs).
Sheet make_sheet(int n, bool flat, bool torn = false) {
  LatticeDef def;
  def.rows = n;
  def.cols = n;
  Sheet sheet{build_lattice(def, Environment{}, {}), {}, {}};
  if (torn) {
    // A fixed pseudo-random choice (a 64-bit LCG), so every run measures the same sheet.
    std::uint64_t z = 12345;
    const auto next = [&z] {
      z = z * 6364136223846793005ULL + 1442695040888963407ULL;
      return static_cast<double>(z >> 11) * 0x1.0p-53;
    };
    ClothModel& model = sheet.model;
    for (std::size_t e = 0; e < model.connector_count(); ++e) {
      set_connector_rest_length(model, static_cast<std::uint32_t>(e),
                                model.connector_rest_length[e] * (0.95 + 0.1 * next()));
      if (next() < 0.1) break_connector(model, static_cast<std::uint32_t>(e));
    }
    for (std::size_t r = 0; r < model.radial_count(); ++r) {
      set_radial_rest_angle(model, static_cast<std::uint32_t>(r), model.radial_rest_angle[r] * (0.95 + 0.05 * next()));
    }
  }
  sheet.position = sheet.model.particle_rest_position;
  sheet.velocity.assign(sheet.position.size(), Vec3{});
  for (std::size_t p = 0; p < sheet.position.size(); ++p) {
    Vec3& x = sheet.position[p];
    if (!flat) x.y = 0.3 * std::sin(0.7 * x.x) * std::cos(0.5 * x.z);
    sheet.velocity[p] = {0.01 * std::cos(x.z), 0.1 * std::sin(x.x), 0.0};
  }
  return sheet;
}

void force_evaluation(benchmark::State& state, ForceKernel kernel, bool flat, bool torn,
                      Precision precision = Precision::float64) {
  const int n = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const Sheet sheet = make_sheet(n, flat, torn);
  ForceBuffers buffers;
  buffers.kernel = kernel;
  buffers.precision = precision;
  buffers.resize(sheet.model);
  std::vector<Vec3> force(sheet.model.particle_count());
  for (auto _ : state) {
    const ForcePowers powers =
        evaluate_forces(sheet.model, sheet.position, sheet.velocity, kAllForceTerms, threads, buffers, force);
    benchmark::DoNotOptimize(powers);
    benchmark::DoNotOptimize(force.data());
  }
  const double particles = static_cast<double>(sheet.model.particle_count());
  state.counters["evals/s"] = benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["ns/particle"] =
      benchmark::Counter(1e-9 * particles, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int threads : {1, 2}) {
    for (int n : {25, 50, 100, 128, 200, 400}) b->Args({n, threads});
  }
  b->ArgNames({"n", "threads"})->UseRealTime()->Unit(benchmark::kMicrosecond);
}

BENCHMARK_CAPTURE(force_evaluation, General, ForceKernel::general, false, false)->Apply(sizes);
BENCHMARK_CAPTURE(force_evaluation, Lattice, ForceKernel::lattice, false, false)->Apply(sizes);
BENCHMARK_CAPTURE(force_evaluation, GeneralFlat, ForceKernel::general, true, false)->Apply(sizes);
BENCHMARK_CAPTURE(force_evaluation, LatticeFlat, ForceKernel::lattice, true, false)->Apply(sizes);
BENCHMARK_CAPTURE(force_evaluation, GeneralTorn, ForceKernel::general, false, true)->Apply(sizes);
BENCHMARK_CAPTURE(force_evaluation, LatticeTorn, ForceKernel::lattice, false, true)->Apply(sizes);
BENCHMARK_CAPTURE(force_evaluation, LatticeFloat32, ForceKernel::lattice, false, false, Precision::float32)
    ->Apply(sizes);
BENCHMARK_CAPTURE(force_evaluation, LatticeFlatFloat32, ForceKernel::lattice, true, false, Precision::float32)
    ->Apply(sizes);

}  // namespace
}  // namespace clothsim
