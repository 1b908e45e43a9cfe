#include "perf/suite.h"

#include <sys/resource.h>

#include <cstdio>
#include <map>
#include <utility>

#include "perf/peak_flops.h"

#include "core/parallel.h"
#include "core/timer.h"
#include "forces/lattice_kernel.h"
#include "scene/scene.h"
#include "scene/scene_simulation.h"
#include "sim/simulation.h"

namespace clothsim {
namespace {

std::size_t peak_rss_bytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return static_cast<std::size_t>(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

constexpr int kFramesPerSecond = 60;

}  // namespace

BenchOptions BenchOptions::quick() {
  BenchOptions options;
  options.sizes = {25, 50, 100};
  options.wall_budget = 0.3;
  options.simulated_cap = 0.4;
  return options;
}

SceneSpec bench_case_scene(int size, IntegratorKind integrator, const BenchOptions& options) {
  const std::string n = std::to_string(size);
  SceneSpec spec = scene_from_paper_args(n + "," + n + ",1,4,1,1400,200,80,5,1", "bench");
  spec.integrator.kind = integrator;
  if (integrator == IntegratorKind::rk4 || integrator == IntegratorKind::symplectic_euler) {
    spec.integrator.time_step = options.explicit_fixed_step;
  }
  spec.backend = options.backend;
  return spec;
}

BenchResult run_bench_case(int size, IntegratorKind integrator, const BenchOptions& options) {
  SceneSpec spec = bench_case_scene(size, integrator, options);
  spec.threads = options.threads;
  Simulation simulation = make_simulation(spec);

  BenchResult result;
  result.size = size;
  result.particles = simulation.model().particle_count();
  result.integrator = integrator;
  const bool adaptive = integrator == IntegratorKind::rkf45 || integrator == IntegratorKind::imex;
  result.time_step = adaptive ? 0.0 : spec.integrator.time_step;

  if (options.backend.kind == Backend::vulkan) {
    // The device's rate is not the CPU kernel's: no FLOP count, no share of the CPU's peak.
    result.kernel = std::string("vulkan-") + to_string(options.backend.resolved_precision(spec.integrator, true));
    if (options.backend.stage_passes) result.kernel += std::string("-") + to_string(*options.backend.stage_passes);
  } else {
    ForceBuffers probe;  // which kernel evaluate_forces() takes for this model
    probe.resize(simulation.model());
    const bool lattice = probe.uses_lattice_kernel();
    result.kernel = lattice ? "lattice" : "general";
    // float32 throughout, or `auto`'s choice frame by frame (sim/precision_choice.h).
    if (options.backend.chooses_by_frame(spec.integrator, lattice)) {
      result.kernel += "-auto";
    } else if (options.backend.resolved_precision(spec.integrator, lattice) == Precision::float32) {
      result.kernel += "-float32";
    }
    result.flops_per_particle = lattice ? kLatticeKernelFlopsPerParticle : 0.0;
  }
  result.threads = simulation.threads();

  const Stopwatch wall;
  bool ok = true;
  for (int frame = 1;; ++frame) {
    const double t = static_cast<double>(frame) / kFramesPerSecond;
    if (t > options.simulated_cap * (1.0 + 1e-12)) break;
    if (!simulation.advance_to(t)) {
      ok = false;
      break;
    }
    if (wall.seconds() >= options.wall_budget) break;
  }
  result.wall_seconds = wall.seconds();
  result.simulated_seconds = simulation.state().time;
  result.status = ok ? "ok" : "failed: " + simulation.failure()->message;
  const IntegratorStats& stats = simulation.integrator_stats();
  result.force_evaluations = stats.force_evaluations;
  result.accepted_steps = stats.accepted_steps;
  result.rejected_steps = stats.rejected_steps;
  result.force_seconds = simulation.profile().seconds(StepStage::forces);
  result.memory_bytes = simulation.memory_bytes();
  result.peak_rss_bytes = peak_rss_bytes();
  return result;
}

std::vector<BenchResult> run_bench_suite(const BenchOptions& options,
                                         const std::function<void(const BenchResult&)>& on_result) {
  // By default every integrator the backend runs.
  std::vector<IntegratorKind> kinds = options.integrators;
  if (kinds.empty()) {
    for (IntegratorKind kind : all_integrator_kinds()) {
      if (unsupported_by_backend(features_of(kind), options.backend).empty()) kinds.push_back(kind);
    }
  }
  std::vector<BenchResult> results;
  // The load average counts the suite's own threads from the cases before, which would talk the
  // automatic choice down to 1 thread as the suite goes on: sample the idle cores once, now.
  const int idle_at_start = idle_hardware_threads();
  std::vector<int> thread_counts;
  for (int size : options.sizes) {
    thread_counts.push_back(resolve_thread_count(options.threads,
                                                 static_cast<std::size_t>(size) * static_cast<std::size_t>(size),
                                                 kParallelThreshold, idle_at_start));
  }
  // The CPU's peak for each thread count, measured before the cases (about 0.1 s each); not for
  // cases on a device, whose rate is not the CPU kernel's (docs/performance.md has the device's
  // roofline).
  // In the precision of the case's forces: float32 has twice the lanes.
  const auto precision_of = [&](int size, IntegratorKind kind) {
    return options.backend.resolved_precision(bench_case_scene(size, kind, options).integrator, true);
  };
  std::map<std::pair<int, Precision>, double> peak_gflops;
  for (std::size_t i = 0; i < options.sizes.size(); ++i) {
    for (IntegratorKind kind : kinds) {
      const std::pair key{thread_counts[i], precision_of(options.sizes[i], kind)};
      if (options.backend.kind == Backend::cpu && peak_gflops.count(key) == 0) {
        peak_gflops[key] = measure_peak_gflops(key.first, key.second);
      }
    }
  }
  for (std::size_t i = 0; i < options.sizes.size(); ++i) {
    const int size = options.sizes[i];
    BenchOptions case_options = options;
    case_options.threads = thread_counts[i];
    for (IntegratorKind kind : kinds) {
      results.push_back(run_bench_case(size, kind, case_options));
      results.back().peak_gflops = peak_gflops[{thread_counts[i], precision_of(size, kind)}];
      if (on_result) on_result(results.back());
    }
  }
  return results;
}

std::string bench_table_header() {
  char line[256];
  std::snprintf(line, sizeof line, "%-9s %-17s %-14s %3s %10s %10s %8s %6s %6s %10s %9s %8s %7s %9s %9s  %s", "lattice",
                "integrator", "kernel", "thr", "evals/s", "us/eval", "GFLOP/s", "peak", "%peak", "p-steps/s", "sim s/s",
                "sim s", "wall s", "sim MiB", "RSS MiB", "status");
  return line;
}

std::string bench_table_row(const BenchResult& r) {
  char line[512];
  const std::string lattice = std::to_string(r.size) + "x" + std::to_string(r.size);
  std::snprintf(line, sizeof line,
                "%-9s %-17s %-14s %3d %10.4g %10.4g %8.3g %6.3g %5.1f%% %10.4g %9.4g %8.4g %7.3g %9.1f %9.1f  %s",
                lattice.c_str(), std::string(to_string(r.integrator)).c_str(), r.kernel.c_str(), r.threads,
                r.evaluations_per_second(), r.microseconds_per_evaluation(), r.achieved_gflops(), r.peak_gflops,
                100.0 * r.peak_share(), r.particle_steps_per_second(), r.realtime_factor(), r.simulated_seconds,
                r.wall_seconds, static_cast<double>(r.memory_bytes) / (1024.0 * 1024.0),
                static_cast<double>(r.peak_rss_bytes) / (1024.0 * 1024.0), r.status.c_str());
  return line;
}

std::string bench_csv(const std::vector<BenchResult>& results) {
  std::string csv =
      "rows,cols,particles,integrator,kernel,threads,time_step,status,wall_seconds,simulated_seconds,"
      "force_evaluations,accepted_steps,rejected_steps,force_seconds,evaluations_per_second,"
      "microseconds_per_evaluation,particle_steps_per_second,simulated_seconds_per_wall_second,memory_bytes,"
      "peak_rss_bytes,flops_per_particle,achieved_gflops,peak_gflops,peak_share\n";
  char line[1024];
  for (const BenchResult& r : results) {
    std::string status = r.status;
    for (char& c : status) {
      if (c == '"') c = '\'';
    }
    std::snprintf(line, sizeof line,
                  "%d,%d,%zu,%s,%s,%d,%.17g,\"%s\",%.17g,%.17g,%llu,%llu,%llu,%.17g,%.17g,%.17g,%.17g,%.17g,%zu,%zu,"
                  "%.17g,%.17g,%.17g,%.17g\n",
                  r.size, r.size, r.particles, std::string(to_string(r.integrator)).c_str(), r.kernel.c_str(),
                  r.threads, r.time_step, status.c_str(), r.wall_seconds, r.simulated_seconds,
                  static_cast<unsigned long long>(r.force_evaluations),
                  static_cast<unsigned long long>(r.accepted_steps), static_cast<unsigned long long>(r.rejected_steps),
                  r.force_seconds, r.evaluations_per_second(), r.microseconds_per_evaluation(),
                  r.particle_steps_per_second(), r.realtime_factor(), r.memory_bytes, r.peak_rss_bytes,
                  r.flops_per_particle, r.achieved_gflops(), r.peak_gflops, r.peak_share());
    csv += line;
  }
  return csv;
}

}  // namespace clothsim
