// The benchmark suite behind `clothsim bench`: the paper's material on square lattices of
// several sizes, run with each integrator for a bounded wall time, measuring throughput.
//
// Each case is `clothsim run --paper-args N,N,1,4,1,1400,200,80,5,1` without output: the centre
// particle anchored, the sheet falling from rest, advanced frame by frame at 60 frames per
// simulated second until the case's wall-time budget or its simulated-time cap is reached. The
// figures are per wall second of the whole simulation loop (forces, integration, checks): force
// evaluations, particle-steps (particles x accepted steps) and simulated seconds. Memory is
// reported two ways: the bytes the simulation holds (model arrays, state and integrator
// workspace, Simulation::memory_bytes()), and the process's peak resident set size so far
// (getrusage), which includes the program itself and everything before the case.
//
// The roofline, read from the command: per case, the force kernel's achieved floating-point rate,
// kLatticeKernelFlopsPerParticle (forces/lattice_kernel.h: 836 operations per particle and
// evaluation, counted from the code) times particles times evaluations over the wall time inside
// force evaluation, and its share of the machine's peak on the case's thread count, in the
// precision of its forces, measured by a multiply-add probe (perf/peak_flops.h) once per thread
// count and precision at the start.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "integrators/integrator.h"
#include "scene/scene.h"

namespace clothsim {

struct BenchOptions {
  std::vector<int> sizes = {25, 50, 100, 200, 400};  // lattice side N (N x N particles)
  std::vector<IntegratorKind> integrators;           // empty: every kind (all_integrator_kinds())
  double wall_budget = 1.5;                          // s of wall time per case (a frame in progress is finished)
  double simulated_cap = 2.0;                        // s of simulated time per case at most
  int threads = 0;                                   // 0: chosen from the lattice size, as `clothsim run` does
  // Step of the explicit fixed-step methods (rk4, symplectic-euler), s: the paper's material is
  // stiff (opposite springs damped with c = 200), and their default 1e-3 s blows up; 2e-4 s is
  // stable for both. rkf45 chooses its own steps; other kinds use their default settings.
  double explicit_fixed_step = 2e-4;
  // Where the cases run (sim/backend.h); the kernel column then names the device's precision.
  BackendSettings backend;
  // The short version: sizes 25, 50, 100 and a fifth of the budget and cap.
  static BenchOptions quick();
};

struct BenchResult {
  int size = 0;  // N
  std::size_t particles = 0;
  IntegratorKind integrator = IntegratorKind::rkf45;
  // Force kernel in use: "lattice" (float64), "lattice-float32", "lattice-auto" (`auto`'s choice
  // frame by frame, sim/precision_choice.h) or "general" on the CPU; "vulkan-float32" or
  // "vulkan-float64".
  std::string kernel;
  int threads = 1;
  double time_step = 0.0;  // s; the fixed step, or 0 for adaptive
  std::string status;      // "ok", or the failure diagnosis
  double wall_seconds = 0.0;
  double simulated_seconds = 0.0;
  std::uint64_t force_evaluations = 0;
  std::uint64_t accepted_steps = 0;
  std::uint64_t rejected_steps = 0;
  double force_seconds = 0.0;       // wall time inside force evaluation
  std::size_t memory_bytes = 0;     // Simulation::memory_bytes()
  std::size_t peak_rss_bytes = 0;   // process peak resident set size after the case
  double flops_per_particle = 0.0;  // per force evaluation; 0 where not counted (the general kernel)
  double peak_gflops = 0.0;         // the machine's measured peak on `threads` threads, forces' precision

  double evaluations_per_second() const {
    return wall_seconds > 0 ? static_cast<double>(force_evaluations) / wall_seconds : 0.0;
  }
  double particle_steps_per_second() const {
    return wall_seconds > 0 ? static_cast<double>(particles) * static_cast<double>(accepted_steps) / wall_seconds : 0.0;
  }
  double realtime_factor() const { return wall_seconds > 0 ? simulated_seconds / wall_seconds : 0.0; }
  double microseconds_per_evaluation() const {
    return force_evaluations > 0 ? 1e6 * force_seconds / static_cast<double>(force_evaluations) : 0.0;
  }
  // The force kernel's floating-point rate, GFLOP/s (0 where not counted), and its share of the peak.
  double achieved_gflops() const {
    return force_seconds > 0 ? flops_per_particle * static_cast<double>(particles) *
                                   static_cast<double>(force_evaluations) / force_seconds / 1e9
                             : 0.0;
  }
  double peak_share() const { return peak_gflops > 0 ? achieved_gflops() / peak_gflops : 0.0; }
};

// The scene of one case: the paper's material on a size x size lattice, with `integrator`.
SceneSpec bench_case_scene(int size, IntegratorKind integrator, const BenchOptions& options);

BenchResult run_bench_case(int size, IntegratorKind integrator, const BenchOptions& options);

// Runs every (size, integrator) case in order, calling `on_result` after each.
std::vector<BenchResult> run_bench_suite(const BenchOptions& options,
                                         const std::function<void(const BenchResult&)>& on_result = {});

// A fixed-width table: the header line, then one line per result.
std::string bench_table_header();
std::string bench_table_row(const BenchResult& result);
// CSV with a header row; numbers in full precision.
std::string bench_csv(const std::vector<BenchResult>& results);

}  // namespace clothsim
