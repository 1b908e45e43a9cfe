// The stages of a step, and the wall time spent in each.
//
// One list (after Box2D's b2SolverStageType) that Simulation::advance_to runs in order, that the
// integrators and the Vulkan backend time their parts by, and that the run profile
// (sim/profile.h, `clothsim run --profile`) and summary.json's "timings" report, so profiles of
// any integrator and either backend compare line for line:
//
//   forces          the right-hand side: forces, accelerations and powers (inside the integrator)
//   integration     the rest of the integrator's step, with its parts:
//     stage sums          Runge-Kutta: each stage's state from the earlier stages' rates
//     jacobians           implicit: the element Jacobians of the linear system
//     assembly            implicit: its block matrix and block Jacobi's diagonal inverses
//     preconditioner setup  implicit: the multigrid levels (Galerkin products, line factors)
//     linear solve        implicit: preconditioned conjugate gradients
//     solution and error  RKF45: the trial solution and its error norm, in one pass
//     solution update     RK4, symplectic Euler: the new state
//     device steps        Vulkan: the device's passes, waited for
//     device transfers    Vulkan: uploads and read-backs of the state and the step control
//   collisions      between steps: particles out of obstacles, the sheet out of itself
//   anchors         between steps: driven anchors arriving, keyframes, anchors letting go
//   events          between steps: tearing, permanent stretching, creasing
//   checks          the state finite and not exploding, the energy balance
//
// The parts of integration are timed inside it: they add up to at most its time.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/timer.h"

namespace clothsim {

enum class StepStage : std::uint8_t {
  forces,
  integration,
  stage_sums,
  jacobians,
  assembly,
  preconditioner_setup,
  linear_solve,
  solution_and_error,
  solution_update,
  device_steps,
  device_transfers,
  collisions,
  anchors,
  events,
  checks,
};
inline constexpr std::size_t kStepStageCount = static_cast<std::size_t>(StepStage::checks) + 1;

struct StepStageInfo {
  StepStage stage;
  std::string_view name;  // as `--profile` and summary.json's "timings" print it
  StepStage parent;       // the stage it is a part of; itself for a stage of the step
};

// Every stage, in the enum's order (which is the order of the step and of the profile).
inline constexpr std::array<StepStageInfo, kStepStageCount> kStepStages = {{
    {StepStage::forces, "forces", StepStage::forces},
    {StepStage::integration, "integration", StepStage::integration},
    {StepStage::stage_sums, "stage sums", StepStage::integration},
    {StepStage::jacobians, "jacobians", StepStage::integration},
    {StepStage::assembly, "assembly", StepStage::integration},
    {StepStage::preconditioner_setup, "preconditioner setup", StepStage::integration},
    {StepStage::linear_solve, "linear solve", StepStage::integration},
    {StepStage::solution_and_error, "solution and error", StepStage::integration},
    {StepStage::solution_update, "solution update", StepStage::integration},
    {StepStage::device_steps, "device steps", StepStage::integration},
    {StepStage::device_transfers, "device transfers", StepStage::integration},
    {StepStage::collisions, "collisions", StepStage::collisions},
    {StepStage::anchors, "anchors", StepStage::anchors},
    {StepStage::events, "events", StepStage::events},
    {StepStage::checks, "checks", StepStage::checks},
}};

constexpr const StepStageInfo& stage_info(StepStage stage) { return kStepStages[static_cast<std::size_t>(stage)]; }
constexpr std::string_view to_string(StepStage stage) { return stage_info(stage).name; }
// A stage of the step itself, not a part of one.
constexpr bool is_step_stage(StepStage stage) { return stage_info(stage).parent == stage; }

// Wall time per stage, s, and which stages were timed at all (a part that an integrator does not
// have is not reported).
class StepProfile {
 public:
  double seconds(StepStage stage) const { return seconds_[index(stage)]; }
  bool timed(StepStage stage) const { return timed_[index(stage)]; }
  void add(StepStage stage, double seconds) {
    seconds_[index(stage)] += seconds;
    timed_[index(stage)] = true;
  }
  // Replaces a stage's time by a total kept elsewhere (an integrator's force timer).
  void set(StepStage stage, double seconds) {
    seconds_[index(stage)] = seconds;
    timed_[index(stage)] = true;
  }
  // Adds every stage of `other`.
  StepProfile& operator+=(const StepProfile& other) {
    for (std::size_t i = 0; i < kStepStageCount; ++i) {
      seconds_[i] += other.seconds_[i];
      timed_[i] = timed_[i] || other.timed_[i];
    }
    return *this;
  }

 private:
  static constexpr std::size_t index(StepStage stage) { return static_cast<std::size_t>(stage); }

  std::array<double, kStepStageCount> seconds_{};
  std::array<bool, kStepStageCount> timed_{};
};

// Adds the lifetime of the object to one stage of a profile:
// `{ StageTimer timer(profile_, StepStage::collisions); ... }`.
class StageTimer {
 public:
  StageTimer(StepProfile& profile, StepStage stage) : profile_(profile), stage_(stage) {}
  ~StageTimer() { profile_.add(stage_, watch_.seconds()); }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  StepProfile& profile_;
  StepStage stage_;
  Stopwatch watch_;
};

}  // namespace clothsim
