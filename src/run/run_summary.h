// summary.json: what a run was and how it went, written by RunWriter::finish (docs/cli.md,
// "summary.json", has every key). Its sections are the records the simulation reports, each from
// its one field list (core/record_fields.h): "integrator" the settings and IntegratorStats,
// "energy" EnergyBalance at the first and last frame, "sheet_changes" SpringEventCounts and
// ModelChanges, "contacts" ContactStatistics, "diagnosis" Diagnosis, "timings" the profile.
#pragma once

#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/record_fields.h"
#include "run/run_status.h"
#include "scene/scene.h"
#include "sim/simulation.h"

namespace clothsim {

// What the output folder knows of a run that the simulation does not.
struct RunRecord {
  std::string version;       // "clothsim_version": its presence marks a clothsim folder
  std::string command_line;  // as the user typed it (the first, for a resumed run)
  std::string resumed_by;    // the resuming command line; empty: never resumed
  double resumed_at = 0.0;   // the time resumed from, s
  RunStatus status = RunStatus::completed;
  const SceneSpec* scene = nullptr;  // as run
  std::size_t frames = 0;            // written, frame 0 included
  double last_time = 0.0;            // s, of the last frame written
  EnergyBalance initial_energy;      // at frame 0
  EnergyBalance last_energy;         // at the last frame written
  double wall_seconds = 0.0;         // the run's wall time, s
  double output_seconds = 0.0;       // of which writing the data files, s
  nlohmann::ordered_json files;      // "files": each file of the folder and its details
};

// The whole summary of `run`, with `simulation` at its last frame.
nlohmann::ordered_json run_summary(const RunRecord& run, const Simulation& simulation);

// A record's fields added to a JSON object, in order (Computed values included; a non-finite
// number is null, as JSON has no infinity).
template <typename Record>
void add_record_json(nlohmann::ordered_json& object, const Record& record) {
  Record::for_each_field(record, [&object](std::string_view name, auto&& field, auto...) {
    const auto& value = field_value(field);
    if constexpr (std::is_floating_point_v<std::remove_cvref_t<decltype(value)>>) {
      object[std::string(name)] =
          std::isfinite(value) ? nlohmann::ordered_json(value) : nlohmann::ordered_json(nullptr);
    } else {
      object[std::string(name)] = value;
    }
  });
}

}  // namespace clothsim
