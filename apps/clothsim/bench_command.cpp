// `clothsim bench`: the fixed benchmark suite of src/perf/suite.h: the paper's material on
// square lattices (25^2 .. 400^2) with every integrator, each case bounded by wall time; prints a
// table as it goes and optionally writes CSV. All flags are checked before anything runs; the
// CSV file is written at the end through a temporary file and a rename, so it is complete or
// absent.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "commands.h"
#include "core/error.h"
#include "memory_check.h"
#include "perf/suite.h"
#include "run/run_memory.h"
#include "run/run_writer.h"
#include "sim/backend.h"

namespace clothsim::cli {
namespace {

struct BenchFlags {
  CLI::App* app = nullptr;
  bool quick = false;
  std::string sizes;
  std::string integrators;
  std::string csv;
  int threads = 0;
  double seconds = 0.0;
  double simulated_cap = 0.0;
  std::string backend;
  int device = 0;
  std::string precision;
  std::string stage_passes;
  MemoryFlags memory;  // --max-memory (memory_check.h)

  bool given(const char* flag) const { return app->count(flag) > 0; }
};

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) items.push_back(item);
  return items;
}

BenchOptions make_options(const BenchFlags& flags) {
  BenchOptions options = flags.quick ? BenchOptions::quick() : BenchOptions{};
  if (flags.given("--sizes")) {
    options.sizes.clear();
    for (const std::string& item : split_list(flags.sizes)) {
      std::size_t used = 0;
      int size = 0;
      try {
        size = std::stoi(item, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != item.size() || item.empty() || size < 2 || size > 4096) {
        throw InputError("--sizes", "",
                         "'" + item + "' is not a lattice side: expected integers in [2, 4096], e.g. 25,50");
      }
      options.sizes.push_back(size);
    }
    if (options.sizes.empty()) throw InputError("--sizes", "", "expected a list of integers in [2, 4096], e.g. 25,50");
  }
  if (flags.given("--integrators")) {
    std::string known;
    for (IntegratorKind kind : all_integrator_kinds())
      known += (known.empty() ? "" : ", ") + std::string(to_string(kind));
    for (const std::string& item : split_list(flags.integrators)) {
      IntegratorKind kind{};
      if (!parse_integrator_kind(item, kind)) {
        throw InputError("--integrators", "", "unknown integrator '" + item + "' (known: " + known + ")");
      }
      options.integrators.push_back(kind);
    }
    if (options.integrators.empty()) throw InputError("--integrators", "", "expected a list of: " + known);
  }
  if (flags.given("--backend") && !parse_backend(flags.backend, options.backend.kind)) {
    throw InputError("--backend", "", "expected cpu or vulkan, got '" + flags.backend + "'");
  }
  if (flags.given("--device")) {
    if (flags.device < 0 || flags.device > 1024) throw InputError("--device", "", "expected an integer in [0, 1024]");
    options.backend.device = static_cast<std::uint32_t>(flags.device);
  }
  if (flags.given("--precision")) {
    PrecisionRequest precision{};
    if (!parse_precision_request(flags.precision, precision)) {
      throw InputError("--precision", "", "expected float64, float32 or auto, got '" + flags.precision + "'");
    }
    options.backend.precision = precision;
  }
  if (flags.given("--stage-passes")) {
    StagePasses passes{};
    if (!parse_stage_passes(flags.stage_passes, passes)) {
      throw InputError("--stage-passes", "", "expected split, fused or chained, got '" + flags.stage_passes + "'");
    }
    if (options.backend.kind != Backend::vulkan) {
      throw InputError("--stage-passes", "", "applies to the vulkan backend only (--backend vulkan)");
    }
    options.backend.stage_passes = passes;
  }
  for (IntegratorKind kind : options.integrators) {
    const std::string unsupported = unsupported_by_backend(features_of(kind), options.backend);
    if (!unsupported.empty()) {
      throw InputError(flags.given("--integrators") ? "--integrators" : "--precision", "",
                       backend_refusal(unsupported, options.backend));
    }
  }
  if (options.integrators.empty()) {
    const std::string unsupported = unsupported_by_backend(features_of(IntegratorKind::rkf45), options.backend);
    if (!unsupported.empty()) throw InputError("--precision", "", backend_refusal(unsupported, options.backend));
  }
  if (flags.given("--threads")) {
    if (flags.threads < 0 || flags.threads > 1024)
      throw InputError("--threads", "", "expected an integer in [0, 1024]");
    options.threads = flags.threads;
  }
  if (flags.given("--seconds")) {
    if (!(flags.seconds > 0.0 && flags.seconds <= 600.0))
      throw InputError("--seconds", "", "expected a number in (0, 600]");
    options.wall_budget = flags.seconds;
  }
  if (flags.given("--sim-cap")) {
    if (!(flags.simulated_cap > 0.0 && flags.simulated_cap <= 3600.0)) {
      throw InputError("--sim-cap", "", "expected a number in (0, 3600]");
    }
    options.simulated_cap = flags.simulated_cap;
  }
  return options;
}

void write_csv(const std::string& path, const std::string& text) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path partial = target.string() + ".partial";
  {
    std::ofstream file(partial, std::ios::binary | std::ios::trunc);
    file << text;
    file.flush();
    if (!file) {
      std::error_code ignored;
      fs::remove(partial, ignored);
      throw OutputError("cannot write " + partial.string());
    }
  }
  std::error_code error;
  fs::rename(partial, target, error);
  if (error) {
    fs::remove(partial, error);
    throw OutputError("cannot write " + target.string());
  }
}

// Every case must fit before any runs (each case's simulation is freed before the next).
void check_bench_memory(const BenchOptions& options, const MemoryFlags& flags) {
  const MemoryLimit limit = memory_limit(flags);
  const std::vector<IntegratorKind> kinds = options.integrators.empty() ? all_integrator_kinds() : options.integrators;
  for (int size : options.sizes) {
    for (IntegratorKind kind : kinds) {
      MemoryEstimate estimate = estimate_simulation_memory(simulation_shape(bench_case_scene(size, kind, options)));
      estimate.add("program", resident_memory());
      check_memory(
          estimate, limit,
          "the case " + std::to_string(size) + " x " + std::to_string(size) + " with " + std::string(to_string(kind)));
    }
  }
  cap_run_growth(limit);
}

int bench(const BenchFlags& flags) {
  const BenchOptions options = make_options(flags);
  check_bench_memory(options, flags.memory);
  if (!flags.csv.empty()) {
    // Fail before minutes of benchmarking, not after, if the CSV cannot be written.
    const std::filesystem::path parent = std::filesystem::path(flags.csv).parent_path();
    if (!parent.empty() && !std::filesystem::is_directory(parent)) {
      throw InputError("--csv", "", "folder '" + parent.string() + "' does not exist");
    }
  }
  std::printf(
      "clothsim bench: paper material (--paper-args N,N,1,4,1,1400,200,80,5,1), 60 fps frames, no output;\n"
      "each case runs until %.3g s wall or %.3g s simulated. rk4 and symplectic-euler use a %.3g s step.\n\n",
      options.wall_budget, options.simulated_cap, options.explicit_fixed_step);
  std::printf("%s\n", bench_table_header().c_str());
  std::fflush(stdout);
  const std::vector<BenchResult> results = run_bench_suite(options, [](const BenchResult& result) {
    std::printf("%s\n", bench_table_row(result).c_str());
    std::fflush(stdout);
  });
  std::printf(
      "\nevals/s: force evaluations per wall second; us/eval: wall time per evaluation; GFLOP/s: the force\n"
      "kernel's rate (836 operations per particle and evaluation, forces/lattice_kernel.h); peak: GFLOP/s\n"
      "of a multiply-add probe on as many threads, in the forces' precision; %%peak: their ratio; p-steps/s:\n"
      "particles x accepted steps per wall second; sim s/s: simulated seconds per wall second (>= 1 is\n"
      "real time); sim MiB: model + state + integrator workspace; RSS MiB: process peak so far.\n");
  if (!flags.csv.empty()) {
    write_csv(flags.csv, bench_csv(results));
    std::printf("wrote %s\n", flags.csv.c_str());
  }
  std::fflush(stdout);
  return kExitSuccess;
}

}  // namespace

Subcommand add_bench_command(CLI::App& parent) {
  auto flags = std::make_shared<BenchFlags>();
  CLI::App* app = parent.add_subcommand("bench", "Run the benchmark suite: throughput per lattice size and integrator");
  flags->app = app;
  app->add_flag("--quick", flags->quick, "short version: sizes 25, 50, 100; 0.3 s wall, 0.4 s simulated per case");
  app->add_option("--sizes", flags->sizes, "lattice sides to run, e.g. 25,50 (default 25,50,100,200,400)")
      ->type_name("N,N,...");
  app->add_option("--integrators", flags->integrators, "integrators to run, e.g. rkf45 (default: all)")
      ->type_name("NAME,...");
  app->add_option("--threads", flags->threads,
                  "worker threads; 0 chooses from the lattice size and the idle cores at the start (default)")
      ->type_name("N");
  app->add_option("--seconds", flags->seconds, "wall-time budget per case, s (default 1.5)")->type_name("S");
  app->add_option("--sim-cap", flags->simulated_cap, "simulated time per case at most, s (default 2)")->type_name("S");
  app->add_option("--csv", flags->csv, "also write the results as CSV to FILE")->type_name("FILE");
  app->add_option("--backend", flags->backend,
                  "where the cases run: cpu (default) or vulkan (every integrator but imex; docs/gpu.md)")
      ->type_name("cpu|vulkan");
  app->add_option("--device", flags->device, "the Vulkan device, as 'clothsim devices' lists them (default 0)")
      ->type_name("N");
  app->add_option(
         "--precision", flags->precision,
         "float64 (the cpu default), float32 (the vulkan default; float32 springs on the cpu) or auto (float32 where "
         "rkf45's tolerances allow it)")
      ->type_name("float32|float64");
  app->add_option("--stage-passes", flags->stage_passes,
                  "the vulkan backend's explicit stages on a lattice: split (three passes a stage: the stage state, "
                  "the springs, the accelerations), fused (one pass a stage) or chained (up to 3 stages a pass in "
                  "float32, 1 in float64); the same results. Default: chained on a GPU, split on a CPU device such "
                  "as lavapipe (docs/gpu.md)")
      ->type_name("split|fused|chained");
  add_memory_flag(*app, flags->memory);
  app->footer(
      "Each case is the paper's material on an N x N lattice held by its centre particle, falling from rest, "
      "advanced at 60 frames per simulated second without writing output.\n"
      "\n"
      "Examples:\n"
      "  clothsim bench\n"
      "  clothsim bench --quick\n"
      "  clothsim bench --sizes 25,50 --integrators rkf45 --csv bench.csv\n"
      "\n"
      "Exit codes:\n"
      "  0    the suite ran (a case whose simulation failed is reported in its row)\n"
      "  2    bad flag value, or a case too large for the memory; nothing was run or written\n"
      "  3    the CSV file could not be written");
  return {app, [flags] { return bench(*flags); }};
}

}  // namespace clothsim::cli
