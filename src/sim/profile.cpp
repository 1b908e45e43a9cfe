#include "sim/profile.h"

#include <algorithm>
#include <cstdio>

namespace clothsim {

std::vector<ProfileRow> simulation_profile_rows(const Simulation& simulation) {
  const StepProfile profile = simulation.profile();
  std::vector<ProfileRow> rows;
  for (const StepStageInfo& info : kStepStages) {
    const bool part = !is_step_stage(info.stage);
    if (part && !profile.timed(info.stage)) continue;
    rows.push_back({std::string(info.name), profile.seconds(info.stage), part ? 1 : 0});
  }
  return rows;
}

std::vector<ProfileRow> profile_rows(const Simulation& simulation, double output_seconds, double wall_seconds) {
  std::vector<ProfileRow> rows;
  double measured = 0.0;
  double integration = 0.0;
  double parts = 0.0;
  for (const ProfileRow& row : simulation_profile_rows(simulation)) {
    const bool ends_parts = row.depth == 0 && parts > 0.0;
    if (ends_parts) {
      rows.push_back({"rest of step", std::max(0.0, integration - parts), 1});
      parts = 0.0;
    }
    if (row.depth == 0) {
      measured += row.seconds;
      if (row.name == to_string(StepStage::integration)) integration = row.seconds;
    } else {
      parts += row.seconds;
    }
    rows.push_back(row);
  }
  if (output_seconds >= 0.0) {
    rows.push_back({"output", output_seconds, 0});
    measured += output_seconds;
  }
  rows.push_back({"other", std::max(0.0, wall_seconds - measured), 0});
  rows.push_back({"total", wall_seconds, 0});
  return rows;
}

std::string format_profile(const std::vector<ProfileRow>& rows, std::uint64_t force_evaluations) {
  double total = 0.0;
  for (const ProfileRow& row : rows) {
    if (row.name == "total") total = row.seconds;
  }
  std::string text = "stage                    seconds    share\n";
  char line[160];
  for (const ProfileRow& row : rows) {
    const std::string name = std::string(static_cast<std::size_t>(2 * row.depth), ' ') + row.name;
    const double share = total > 0.0 ? 100.0 * row.seconds / total : 0.0;
    std::snprintf(line, sizeof line, "%-22s %9.3f  %6.1f%%", name.c_str(), row.seconds, share);
    text += line;
    if (row.name == "forces" && force_evaluations > 0) {
      std::snprintf(line, sizeof line, "   %llu evaluations, %.1f us each",
                    static_cast<unsigned long long>(force_evaluations),
                    1e6 * row.seconds / static_cast<double>(force_evaluations));
      text += line;
    }
    text += "\n";
  }
  return text;
}

}  // namespace clothsim
