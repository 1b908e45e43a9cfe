// The run profile: where the wall time of a run went, phase by phase.
//
// The phases are the ones the code has, each timed where it runs: force evaluation and the
// integrator's own work (Simulation::profile(), with the integrator's sub-phases such as stage
// sums and the solution and error pass), the events between steps (anchors, tearing, plasticity, creasing),
// the checks between steps, and what the caller measures around the
// simulation (writing output). "other" is the rest of the wall time (setup, the frame loop, the
// progress bar), so the rows add up to the total. Phases that a run does not have are not listed.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/simulation.h"

namespace clothsim {

struct ProfileRow {
  std::string name;
  double seconds = 0.0;
  int depth = 0;  // 0: a phase of the run; 1: a sub-phase of the row above
};

// Rows for `simulation`, plus "output" (if `output_seconds` >= 0), "other" and "total" from
// `wall_seconds`, the wall time of the whole run.
std::vector<ProfileRow> profile_rows(const Simulation& simulation, double output_seconds, double wall_seconds);

// The rows as an aligned text table with seconds, share of the total and, for the force
// evaluations, the time per evaluation.
std::string format_profile(const std::vector<ProfileRow>& rows, std::uint64_t force_evaluations);

}  // namespace clothsim
