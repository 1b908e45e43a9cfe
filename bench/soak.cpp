// clothsim_soak: long runs that must stay healthy (issue 11, item 7). Runs one built-in scene for
// a long simulated time (an hour by default) and samples, every --every simulated seconds, the
// process's resident memory and the energy balance; at the end it says whether memory stayed flat
// from the second sample on (one interval in: the integrator allocates everything up front, but
// the collision stage's pair lists grow to the most contacts the sheet makes, which a folding sheet
// reaches only after a while) and how far the balance error went, against the blow-up check's
// energy scale.
//
//   clothsim_soak SCENE [--duration S] [--every S] [--csv FILE]
//
// It exits 1 if memory grew by more than kMemoryGrowthLimit after the second sample, if the
// simulation failed, or if the balance error ever left [-limit, +limit] times the scale, with
// limit the scene's integrator.energy_error_limit. bench/soak.sh runs the standard set and
// docs/performance.md ("Soak") has the figures.
#include <unistd.h>

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "core/error.h"
#include "core/timer.h"
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

int usage(const char* message) {
  std::fprintf(stderr, "clothsim_soak: %s\nusage: clothsim_soak SCENE [--duration S] [--every S] [--csv FILE]\n",
               message);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage("needs a built-in scene name");
  const std::string name = argv[1];
  double duration = 3600.0;
  double every = 60.0;
  std::string csv_path;
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
  } catch (const InputError& error) {
    return usage(error.what());
  }
  SimulationSettings settings;
  settings.integrator = spec.integrator;
  settings.threads = spec.threads;
  ClothModel model = build_model(spec);
  ClothState initial = build_initial_state(model, spec);
  Simulation simulation(std::move(model), std::move(initial), settings);

  std::FILE* csv = csv_path.empty() ? nullptr : std::fopen(csv_path.c_str(), "w");
  if (!csv_path.empty() && csv == nullptr) return usage(("cannot write " + csv_path).c_str());
  const char* header =
      "time,wall_seconds,resident_bytes,simulation_bytes,accepted_steps,total_energy,balance_error,"
      "energy_scale,error_over_scale,broken_connectors\n";
  if (csv != nullptr) std::fputs(header, csv);

  const double limit = spec.integrator.energy_error_limit;
  const Stopwatch wall;
  long long first_resident = -1;
  long long peak_growth = 0;
  double worst_ratio = 0.0;  // largest |error| / scale over the samples
  bool ok = true;
  const auto samples = static_cast<std::int64_t>(std::ceil(duration / every - 1e-9));
  for (std::int64_t k = 0; k <= samples; ++k) {
    const double t = std::min(duration, static_cast<double>(k) * every);
    if (!simulation.advance_to(t)) {
      std::fprintf(stderr, "clothsim_soak: %s failed %s\n", name.c_str(), simulation.failure()->message.c_str());
      ok = false;
      break;
    }
    const long long resident = resident_bytes();
    if (k == 1) first_resident = resident;
    if (k >= 1) peak_growth = std::max(peak_growth, resident - first_resident);
    const EnergyBalance balance = simulation.energy_balance();
    const double ratio = std::abs(balance.error()) / simulation.energy_scale();
    worst_ratio = std::max(worst_ratio, ratio);
    if (csv != nullptr) {
      std::fprintf(csv, "%.17g,%.6g,%lld,%zu,%" PRIu64 ",%.17g,%.17g,%.17g,%.6g,%zu\n", t, wall.seconds(), resident,
                   simulation.memory_bytes(), simulation.integrator_stats().accepted_steps, balance.energy.total(),
                   balance.error(), simulation.energy_scale(), ratio, simulation.model_changes().broken_connectors);
      std::fflush(csv);
    }
  }
  if (csv != nullptr) std::fclose(csv);

  const bool flat = peak_growth <= kMemoryGrowthLimit;
  const bool balanced = worst_ratio <= limit;
  std::printf("%s: %.6g s simulated in %.1f s wall, %" PRIu64 " steps; ", name.c_str(), simulation.state().time,
              wall.seconds(), simulation.integrator_stats().accepted_steps);
  if (first_resident < 0) {
    std::printf("memory not measured (stopped before t = %g s); ", std::min(every, duration));
  } else {
    std::printf("resident memory %.1f MiB at t = %g s, largest growth after it %lld bytes (%s); ",
                static_cast<double>(first_resident) / (1 << 20), std::min(every, duration), peak_growth,
                flat ? "flat" : "GROWS");
  }
  std::printf("largest |balance error| / energy scale %.3g (limit %g: %s)%s\n", worst_ratio, limit,
              balanced ? "within" : "OUTSIDE", ok ? "" : "; FAILED");
  return ok && flat && balanced ? 0 : 1;
}
