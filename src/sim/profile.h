// The run profile: where the wall time of a run went, stage by stage.
//
// The rows are the stages of the step (core/step_profile.h) in their order, each timed where it
// runs: the stages of the step always, and the parts of integration an integrator has (stage
// sums, solution and error, ...), with "rest of step" for what the parts leave of it; then what
// the caller measures around the simulation (writing output), and "other", the rest of the wall
// time (setup, the frame loop, the progress bar), so the rows add up to the total.
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

// The stages' rows for `simulation` alone: the stages of the step (depth 0) and the parts of
// integration that were timed (depth 1), by their StepStage names.
std::vector<ProfileRow> simulation_profile_rows(const Simulation& simulation);

// The rows of a run: the stages' rows with "rest of step" after the parts of integration, plus
// "output" (if `output_seconds` >= 0), "other" and "total" from `wall_seconds`, the wall time of
// the whole run.
std::vector<ProfileRow> profile_rows(const Simulation& simulation, double output_seconds, double wall_seconds);

// The rows as an aligned text table with seconds, share of the total and, for the force
// evaluations, the time per evaluation.
std::string format_profile(const std::vector<ProfileRow>& rows, std::uint64_t force_evaluations);

}  // namespace clothsim
