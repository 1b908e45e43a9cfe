#include "sim/profile.h"

#include <algorithm>
#include <cstdio>

namespace clothsim {

std::vector<ProfileRow> profile_rows(const Simulation& simulation, double output_seconds, double wall_seconds) {
  const StepProfile& profile = simulation.profile();
  std::vector<ProfileRow> rows;
  rows.push_back({"forces", profile.forces, 0});
  rows.push_back({"integration", profile.integration, 0});
  double timed_phases = 0.0;
  for (const PhaseTime& phase : simulation.integration_phases()) {
    rows.push_back({std::string(phase.name), phase.seconds, 1});
    timed_phases += phase.seconds;
  }
  if (timed_phases > 0.0) rows.push_back({"rest of step", std::max(0.0, profile.integration - timed_phases), 1});
  rows.push_back({"collisions", profile.collisions, 0});
  rows.push_back({"events", profile.events, 0});
  rows.push_back({"checks", profile.checks, 0});
  double measured = profile.forces + profile.integration + profile.collisions + profile.events + profile.checks;
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
  std::string text = "phase                  seconds    share\n";
  char line[160];
  for (const ProfileRow& row : rows) {
    const std::string name = std::string(static_cast<std::size_t>(2 * row.depth), ' ') + row.name;
    const double share = total > 0.0 ? 100.0 * row.seconds / total : 0.0;
    std::snprintf(line, sizeof line, "%-20s %9.3f  %6.1f%%", name.c_str(), row.seconds, share);
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
