#include "run/run_summary.h"

#include "sim/profile.h"

namespace clothsim {
namespace {

using ordered_json = nlohmann::ordered_json;

// A finite number, or null (JSON has no infinity; nlohmann would write null anyway, this says so).
ordered_json number_or_null(double value) { return std::isfinite(value) ? ordered_json(value) : ordered_json(nullptr); }

// A ratio, or null where the denominator is not positive.
ordered_json ratio_or_null(double numerator, double denominator) {
  return denominator > 0.0 ? number_or_null(numerator / denominator) : ordered_json(nullptr);
}

ordered_json lattice_json(const ClothModel& model) {
  return ordered_json{{"rows", model.rows},
                      {"cols", model.cols},
                      {"particles", model.particle_count()},
                      {"connectors", model.connector_count()},
                      {"radial_springs", model.radial_count()},
                      {"anchors", model.anchor_count()}};
}

// The precision of the forces, `auto` resolved (sim/backend.h): "float64" or "float32", or where
// the run chose frame by frame (sim/precision_choice.h), the one of every window, or "mixed" (its
// steps at rest, float64, not counted).
std::string precision_json(const Simulation& simulation) {
  const bool lattice = lattice_forces(simulation.model(), simulation.settings().kernel);
  const PrecisionChoice& choice = simulation.precision_choice();
  if (choice.active()) {
    const PrecisionChoiceStats& windows = choice.stats();
    if (windows.float64_windows == 0) return to_string(Precision::float32);
    return windows.float32_windows == 0 ? to_string(Precision::float64) : "mixed";
  }
  return to_string(simulation.settings().backend.resolved_precision(simulation.settings().integrator, lattice));
}

// `auto`'s choice frame by frame: its windows, the largest drift measured and the limit; null
// where the run did not choose.
ordered_json precision_choice_json(const Simulation& simulation) {
  const PrecisionChoice& choice = simulation.precision_choice();
  if (!choice.active()) return nullptr;
  ordered_json json = ordered_json::object();
  add_record_json(json, choice.stats());
  json["drift_limit"] = choice.drift_limit();
  json["window"] = kPrecisionWindow;
  return json;
}

// The settings of the method, then its statistics, then two rates derived from them.
ordered_json integrator_json(const Simulation& simulation, double simulated_time) {
  const IntegratorSettings& settings = simulation.settings().integrator;
  const IntegratorStats stats = simulation.integrator_stats();
  ordered_json integrator{{"method", std::string(to_string(settings.kind))},
                          {"precision", precision_json(simulation)},
                          {"relative_tolerance", settings.relative_tolerance},
                          {"absolute_tolerance", settings.absolute_tolerance},
                          {"time_step", settings.time_step},
                          {"cg_tolerance", settings.cg_tolerance},
                          {"cg_max_iterations", settings.cg_max_iterations},
                          {"precision_choice", precision_choice_json(simulation)}};
  add_record_json(integrator, stats);
  if (stats.accepted_steps == 0) {
    // No step taken: the step sizes are not 0 (or infinite), they are not there.
    for (const char* step : {"smallest_step", "largest_step", "last_step"}) integrator[step] = nullptr;
  }
  const auto steps = static_cast<double>(stats.accepted_steps);
  integrator["cg_iterations_per_step"] = ratio_or_null(static_cast<double>(stats.cg_iterations), steps);
  integrator["steps_per_simulated_second"] = ratio_or_null(steps, simulated_time);
  return integrator;
}

ordered_json energy_json(const EnergyBalance& balance, double time) {
  ordered_json energy{{"time", time}};
  add_record_json(energy, balance);
  return energy;
}

// Tearing, permanent stretching and creasing (DESIGN.md section 3), over the whole run.
ordered_json sheet_changes_json(const Simulation& simulation, const EnergyBalance& last) {
  ordered_json changes = ordered_json::object();
  add_record_json(changes, simulation.event_totals());
  add_record_json(changes, simulation.model_changes());
  changes["pieces"] = count_pieces(simulation.model());
  changes["plastic_work"] = last.plastic_work;
  changes["fracture_work"] = last.fracture_work;
  return changes;
}

// Contacts (collision/): obstacle contacts (particles) and self-contacts (pairs of elements)
// after the last step, summed over accepted steps and the most after one step, the self pass's
// impacts, impact zones and pairs it left touching, and the energy the collision stage changed.
ordered_json contacts_json(const Simulation& simulation, const EnergyBalance& last) {
  const ClothModel& model = simulation.model();
  ordered_json contacts{{"colliders", model.colliders.size()}, {"self_collision", model.collision.self}};
  add_record_json(contacts, simulation.contact_statistics());
  contacts["contact_work"] = last.contact_work;
  return contacts;
}

// The profile's rows of the simulation (sim/profile.h), the output and the whole run.
ordered_json timings_json(const RunRecord& run, const Simulation& simulation) {
  ordered_json timings{{"wall_seconds", run.wall_seconds}};
  ordered_json phases = ordered_json::object();
  for (const ProfileRow& row : simulation_profile_rows(simulation)) {
    (row.depth == 0 ? timings : phases)[row.name] = row.seconds;
  }
  timings["output"] = run.output_seconds;
  timings["realtime_factor"] = ratio_or_null(run.last_time, run.wall_seconds);
  timings["integration_phases"] = phases;
  return timings;
}

}  // namespace

ordered_json run_summary(const RunRecord& run, const Simulation& simulation) {
  ordered_json summary;
  summary["clothsim_version"] = run.version;
  summary["command_line"] = run.command_line;
  if (!run.resumed_by.empty()) {
    summary["resumed"] = ordered_json{{"command_line", run.resumed_by}, {"from_time", run.resumed_at}};
  }
  summary["status"] = std::string(to_string(run.status));
  if (run.status == RunStatus::failed && simulation.failure()) {
    ordered_json diagnosis = ordered_json::object();
    add_record_json(diagnosis, *simulation.failure());
    summary["diagnosis"] = diagnosis;
  }
  summary["scene"] = ordered_json(scene_to_json(*run.scene));
  summary["lattice"] = lattice_json(simulation.model());
  summary["frames"] = run.frames;
  summary["fps"] = run.scene->output.fps;
  summary["simulated_time"] = run.last_time;
  summary["integrator"] = integrator_json(simulation, run.last_time);
  summary["energy"] = ordered_json{{"initial", energy_json(run.initial_energy, 0.0)},
                                   {"final", energy_json(run.last_energy, run.last_time)}};
  summary["sheet_changes"] = sheet_changes_json(simulation, run.last_energy);
  summary["contacts"] = contacts_json(simulation, run.last_energy);
  summary["timings"] = timings_json(run, simulation);
  summary["threads"] = simulation.threads();
  summary["memory_bytes"] = simulation.memory_bytes();
  summary["files"] = run.files;
  return summary;
}

}  // namespace clothsim
