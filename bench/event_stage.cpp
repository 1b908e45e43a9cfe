// Micro-benchmark of the event stage (events/spring_events.h) against one force evaluation, on
// the same 128 x 128 wavy sheet of the paper's material as force_kernels.cpp, with limits that
// nothing reaches: the common step, in which the stage only checks. *Stretch: yield strain only;
// *Crease: yield angles only; *All: break strain, yield strain and both yield angles. An RKF45
// step costs 6 force evaluations; the stage runs once per accepted step.
//
//   build/bench/bench/clothsim_microbench --benchmark_filter=Events --benchmark_repetitions=5
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "events/spring_events.h"
#include "model/spring_limits.h"

namespace clothsim {
namespace {

void event_stage(benchmark::State& state, bool stretch, bool crease, bool tear) {
  const int n = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  LatticeDef def;
  def.rows = n;
  def.cols = n;
  ClothModel model = build_lattice(def, Environment{}, {});
  SpringLimits limits;
  if (stretch) limits.yield_strain = 0.5;
  if (tear) limits.break_strain = 1.0;
  if (crease) limits.adjacent_yield_angle = limits.opposite_yield_angle = 1.0;
  apply_spring_limits(model, limits);
  ClothState cloth = make_rest_state(model);
  for (Vec3& x : cloth.position) x.y = 0.3 * std::sin(0.7 * x.x) * std::cos(0.5 * x.z);
  SpringEvents events;
  for (auto _ : state) {
    const SpringEventCounts counts = events.apply(model, cloth, threads);
    benchmark::DoNotOptimize(counts);
  }
  const double particles = static_cast<double>(model.particle_count());
  state.counters["ns/particle"] =
      benchmark::Counter(1e-9 * particles, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int threads : {1, 2}) b->Args({128, threads});
  b->ArgNames({"n", "threads"})->UseRealTime()->Unit(benchmark::kMicrosecond);
}

BENCHMARK_CAPTURE(event_stage, EventsStretch, true, false, false)->Apply(sizes);
BENCHMARK_CAPTURE(event_stage, EventsCrease, false, true, false)->Apply(sizes);
BENCHMARK_CAPTURE(event_stage, EventsAll, true, true, true)->Apply(sizes);

}  // namespace
}  // namespace clothsim
