// How a run ended: summary.json's "status", the result of run_scene() and the tools' exit codes.
#pragma once

#include <cstdint>
#include <string_view>

namespace clothsim {

// Written to summary.json as "completed", "at_rest", "failed", "interrupted".
enum class RunStatus : std::uint8_t {
  completed,    // every frame up to the duration was written
  at_rest,      // stopped early: the kinetic energy stayed below output.rest_kinetic_energy for output.rest_duration
  failed,       // the simulation stopped with a diagnosis; frames up to the last good one are kept
  interrupted,  // stopped by the user (SIGINT) after a complete frame
};

std::string_view to_string(RunStatus status);

}  // namespace clothsim
