// clothsim_soak: long runs that must stay healthy (issue 11, item 7). Runs one built-in scene for
// a long simulated time (an hour by default) and samples, every --every simulated seconds, the
// process's resident memory and the energy balance; at the end it says whether memory stayed flat
// from the second sample on (one interval in: the integrator allocates everything up front, but
// the collision stage's pair lists grow to the most contacts the sheet makes, which a folding sheet
// reaches only after a while) and how far the balance error went, against the blow-up check's
// energy scale.
//
//   clothsim_soak SCENE [--duration S] [--every S] [--csv FILE] [--threads N] [--set KEY=VALUE]...
//   clothsim_soak --list
//
// --checkpoint FILE saves the soak at every sample (io/checkpoint.h, atomically) and, when FILE
// exists at the start, resumes from it: the run goes on bit for bit, the CSV keeps its rows up to
// the checkpoint and its wall times add up across the segments, and memory is judged per segment
// (from the segment's first sample). A soak longer than one sitting runs in segments.
//
// --set changes a scene parameter by its key, as the command's --set does (for example
// collision.self=true); --threads overrides the scene's thread count (the results are the same
// bits for any count, so bench/soak.sh runs two scenes at once on one thread each).
//
// It exits 1 if memory grew by more than kMemoryGrowthLimit after the second sample, if the
// simulation failed, or if the balance error ever left [-limit, +limit] times the scale, with
// limit the scene's integrator.energy_error_limit. bench/soak.sh runs the standard set and
// docs/performance.md ("Soak") has the figures.
#include <time.h>
#include <unistd.h>

#include <cinttypes>
#include <filesystem>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/timer.h"
#include "io/checkpoint.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene/scene_model.h"
#include "sim/simulation.h"

namespace {

using namespace clothsim;

// Growth of the resident memory after the reference sample that counts as a leak, bytes.
constexpr long long kMemoryGrowthLimit = 1 << 20;

// Resident memory of this process, bytes (/proc/self/statm), or -1.
long long resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  long long pages_total = 0;
  long long pages_resident = 0;
  if (!(statm >> pages_total >> pages_resident)) return -1;
  return pages_resident * ::sysconf(_SC_PAGESIZE);
}

// CPU time of this process so far, s: the soak's cost measure, since it does not count time the
// process waited for the CPU (a loaded machine) or was stopped (SIGSTOP while something else is
// measured); on one thread it is what the wall time would be on an idle machine.
double process_cpu_seconds() {
  timespec now{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

// Cuts the CSV at `path` back to its header and the rows up to simulated time `time`.
void keep_rows_up_to(const std::string& path, double time) {
  std::ifstream in(path);
  std::string kept;
  std::string line;
  for (bool header = true; std::getline(in, line); header = false) {
    if (!header && std::atof(line.c_str()) > time * (1.0 + 1e-12)) break;
    kept += line + "\n";
  }
  in.close();
  std::ofstream(path, std::ios::trunc) << kept;
}

int usage(const char* message) {
  std::fprintf(stderr,
               "clothsim_soak: %s\nusage: clothsim_soak SCENE [--duration S] [--every S] [--csv FILE] [--threads N] "
               "[--set KEY=VALUE]... [--checkpoint FILE]\n",
               message);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage("needs a built-in scene name");
  const std::string name = argv[1];
  if (name == "--list") {  // the built-in scenes' names, one a line (bench/soak.sh runs them all)
    for (const BuiltinScene& scene : builtin_scenes()) std::printf("%s\n", scene.name.c_str());
    return 0;
  }
  double duration = 3600.0;
  double every = 60.0;
  std::string csv_path;
  std::string checkpoint_path;
  int threads = -1;  // the scene's own
  std::vector<std::string> assignments;
  for (int i = 2; i < argc; ++i) {
    const std::string flag = argv[i];
    if (i + 1 >= argc) return usage(("missing value of " + flag).c_str());
    const std::string value = argv[++i];
    if (flag == "--duration") {
      duration = std::atof(value.c_str());
    } else if (flag == "--every") {
      every = std::atof(value.c_str());
    } else if (flag == "--csv") {
      csv_path = value;
    } else if (flag == "--threads") {
      threads = std::atoi(value.c_str());
      if (threads < 0) return usage("--threads must be 0 (automatic) or more");
    } else if (flag == "--checkpoint") {
      checkpoint_path = value;
    } else if (flag == "--set") {
      assignments.push_back(value);
    } else {
      return usage(("unknown flag " + flag).c_str());
    }
  }
  if (!(duration > 0.0) || !(every > 0.0) || every >= duration) {
    return usage("--duration and --every must be positive, --every below --duration");
  }

  SceneSpec spec;
  try {
    spec = builtin_scene(name);
    for (const std::string& text : assignments) {
      const std::size_t equals = text.find('=');
      if (equals == std::string::npos) return usage(("--set takes KEY=VALUE, not " + text).c_str());
      set_scene_field(spec, text.substr(0, equals), text.substr(equals + 1), "--set");
    }
    if (threads >= 0) spec.threads = threads;
  } catch (const InputError& error) {
    return usage(error.what());
  }
  SimulationSettings settings;
  settings.integrator = spec.integrator;
  settings.threads = spec.threads;
  ClothModel model = build_model(spec);
  ClothState initial = build_initial_state(model, spec);
  Simulation simulation(std::move(model), std::move(initial), settings);

  // Resuming: the simulation and the soak's own counters from the checkpoint, and the CSV cut
  // back to the samples the checkpoint had seen (a run stopped between two samples wrote rows the
  // checkpoint does not know).
  double wall_before = 0.0;  // wall seconds of the earlier segments
  double cpu_before = 0.0;   // CPU seconds of the earlier segments
  double worst_ratio = 0.0;  // largest |balance error| / scale over the samples, all segments
  std::int64_t first_sample = 0;
  const bool resuming = !checkpoint_path.empty() && std::filesystem::exists(checkpoint_path);
  if (resuming) {
    try {
      CheckpointReader reader(checkpoint_path);
      reader.value("soak_wall_seconds", wall_before);
      reader.value("soak_cpu_seconds", cpu_before);
      reader.value("soak_worst_ratio", worst_ratio);
      simulation.transfer_state(reader);
      reader.finish();
    } catch (const std::exception& error) {
      std::fprintf(stderr, "clothsim_soak: cannot resume: %s\n", error.what());
      return 2;
    }
    first_sample = std::llround(simulation.state().time / every) + 1;
    if (!csv_path.empty()) keep_rows_up_to(csv_path, simulation.state().time);
  }

  std::FILE* csv = csv_path.empty() ? nullptr : std::fopen(csv_path.c_str(), resuming ? "a" : "w");
  if (!csv_path.empty() && csv == nullptr) return usage(("cannot write " + csv_path).c_str());
  const char* header =
      "time,wall_seconds,cpu_seconds,resident_bytes,simulation_bytes,accepted_steps,total_energy,balance_error,"
      "energy_scale,error_over_scale,broken_connectors\n";
  if (csv != nullptr && !resuming) std::fputs(header, csv);

  const double limit = spec.integrator.energy_error_limit;
  const Stopwatch wall;
  const double cpu_start = process_cpu_seconds();
  long long first_resident = -1;  // the reference: this process's first sample after the start
  double reference_time = 0.0;
  long long peak_growth = 0;
  bool ok = true;
  const auto samples = static_cast<std::int64_t>(std::ceil(duration / every - 1e-9));
  for (std::int64_t k = first_sample; k <= samples; ++k) {
    const double t = std::min(duration, static_cast<double>(k) * every);
    if (!simulation.advance_to(t)) {
      std::fprintf(stderr, "clothsim_soak: %s failed %s\n", name.c_str(), simulation.failure()->message.c_str());
      ok = false;
      break;
    }
    const long long resident = resident_bytes();
    const bool reference = k == std::max<std::int64_t>(first_sample, 1);
    if (reference) {
      first_resident = resident;
      reference_time = t;
    }
    if (k > first_sample || reference) peak_growth = std::max(peak_growth, resident - first_resident);
    const EnergyBalance balance = simulation.energy_balance();
    const double ratio = std::abs(balance.error()) / simulation.energy_scale();
    worst_ratio = std::max(worst_ratio, ratio);
    const double wall_total = wall_before + wall.seconds();
    const double cpu_total = cpu_before + process_cpu_seconds() - cpu_start;
    if (csv != nullptr) {
      std::fprintf(csv, "%.17g,%.6g,%.6g,%lld,%zu,%" PRIu64 ",%.17g,%.17g,%.17g,%.6g,%zu\n", t, wall_total, cpu_total,
                   resident,
                   simulation.memory_bytes(), simulation.integrator_stats().accepted_steps, balance.energy.total(),
                   balance.error(), simulation.energy_scale(), ratio, simulation.model_changes().broken_connectors);
      std::fflush(csv);
    }
    if (!checkpoint_path.empty()) {
      write_checkpoint(checkpoint_path, [&](StateArchive& archive) {
        double w = wall_total;
        archive.value("soak_wall_seconds", w);
        double c = cpu_total;
        archive.value("soak_cpu_seconds", c);
        archive.value("soak_worst_ratio", worst_ratio);
        simulation.transfer_state(archive);
      });
    }
  }
  if (csv != nullptr) std::fclose(csv);

  const bool flat = peak_growth <= kMemoryGrowthLimit;
  const bool balanced = worst_ratio <= limit;
  std::string label = name;
  for (const std::string& text : assignments) label += " " + text;
  std::printf("%s: %.6g s simulated in %.1f s wall, %.1f s CPU%s, %" PRIu64 " steps; ", label.c_str(),
              simulation.state().time, wall_before + wall.seconds(), cpu_before + process_cpu_seconds() - cpu_start,
              resuming ? " (resumed)" : "", simulation.integrator_stats().accepted_steps);
  if (first_resident < 0) {
    std::printf("memory not measured (stopped before t = %g s); ", std::min(every, duration));
  } else {
    std::printf("resident memory %.1f MiB at t = %g s, largest growth after it %lld bytes (%s); ",
                static_cast<double>(first_resident) / (1 << 20), reference_time, peak_growth,
                flat ? "flat" : "GROWS");
  }
  std::printf("largest |balance error| / energy scale %.3g (limit %g: %s)%s\n", worst_ratio, limit,
              balanced ? "within" : "OUTSIDE", ok ? "" : "; FAILED");
  return ok && flat && balanced ? 0 : 1;
}
