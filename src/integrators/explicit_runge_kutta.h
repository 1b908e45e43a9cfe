// Explicit Runge-Kutta integrators driven by a Butcher tableau.
//
// ExplicitRungeKutta computes the stages of one trial step of size h from the current state;
// AdaptiveRungeKutta wraps it in step-size control (RKF45), FixedStepRungeKutta takes steps of
// the configured size (RK4, or any tableau in tests). All scratch arrays are allocated in the
// constructor.
//
// Memory. The stages are kept in the form of a Runge-Kutta-Nystrom method: for y = (x, v) with
// x' = v, the stage velocity V_i = v + h sum_j a_ij K_j is the position rate of stage i, so the
// stage position x + h sum_j a_ij V_j equals
//   x + h (sum_j a_ij) v + h^2 sum_l (sum_j a_ij a_jl) K_l,
// and the same holds for the solution and error rows with b_i or b_i - b^_i in place of a_ij.
// Only the accelerations K_i are kept per stage, not the position rates (copies of the stage
// velocities): 24 bytes per particle and stage less. The combinations are the same method, equal
// up to rounding. The trial solution is written into the stage arrays, which are free once the
// last stage is evaluated, and the error estimate is formed piece by piece on the stack inside the
// solution pass: the workspace is s accelerations and one stage state, (s + 2) x 24 bytes per
// particle besides the force buffers (docs/performance.md, "Memory"), and 8 bytes per 1024
// particles for the error norm's block maxima, not counted.
//
// Passes. Each stage's positions and velocities are formed in one parallel sweep, and so are the
// trial solution and, for RKF45, its error estimate and error norm: the accelerations a block
// needs are read from memory once, and each sweep is one fork and join. Every value is the same
// sum, in the same order, as when each array had its own sweep, so the fusion changed no result
// (docs/performance.md, "The integrator").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "integrators/dynamics.h"
#include "integrators/integrator.h"
#include "integrators/step_control.h"
#include "integrators/tableau.h"

namespace clothsim {

// A row of weights w (a stage's a_i, b or b - b^) in Nystrom form: the combination
// h sum_i w_i (V_i, K_i) is (h velocity_sum v + h^2 sum_l position_l K_l, h sum_l w_l K_l).
struct NystromRow {
  double velocity_sum = 0.0;                  // sum_i w_i
  std::array<double, kMaxStages> position{};  // sum_i w_i a_il
  std::array<double, kMaxStages> velocity{};  // w_l
};
NystromRow nystrom_row(const ButcherTableau& tableau, const std::array<double, kMaxStages>& weights);

class ExplicitRungeKutta : public Integrator {
 public:
  ExplicitRungeKutta(const ClothModel& model, const IntegratorSettings& settings, const ForceOptions& options,
                     const ButcherTableau& tableau);
  const ButcherTableau& tableau() const { return tableau_; }
  std::size_t workspace_bytes() const override;
  // Both evaluations in the first two stage arrays, which every step writes before it reads.
  std::optional<double> float32_acceleration_error(const ClothState& state) override;
  void set_force_precision(Precision precision) override;
  // The bytes workspace_bytes() reports for a method of `stages` stages and `particles`
  // particles, besides the force buffers (ForceBuffers::bytes_for) (sim/memory_estimate.h).
  static std::size_t workspace_bytes_for(int stages, std::size_t particles);

 protected:
  // Evaluates every stage of a step of size h from `state`.
  void compute_stages(const ClothState& state, double h);
  // Writes the stage state state + h sum_i w_i (V_i, K_i) for the row w into the stage arrays
  // (without the anchor constraint), positions and velocities in one sweep.
  void combine_stage(const NystromRow& row, double h, const ClothState& state);
  // The solution pass: writes the propagated solution state + h sum_i b_i (V_i, K_i) into the
  // stage arrays, and its work integrals into trial_work_. With an error row (b - b^), the same
  // sweep forms the error estimate h sum_i (b_i - b^_i) (V_i, K_i) and writes into block_error
  // the largest scaled error of each block of 1024 particles (the bits of a non-negative double,
  // NaN where a value is non-finite; see AdaptiveRungeKutta).
  void combine_solution(const ClothState& state, double h, const NystromRow* error_row = nullptr,
                        std::span<double> block_error = {});
  // Accepts the solution in the stage arrays as the new state at time t: exact anchor positions,
  // statistics.
  void accept(ClothState& state, double h, double t);

  // The work integrals of the trial solution, J.
  struct Work {
    double damping = 0.0;
    double drag = 0.0;
    double anchor = 0.0;
  };

  const ClothModel& model_;
  IntegratorSettings settings_;
  ButcherTableau tableau_;
  std::array<NystromRow, kMaxStages> stage_rows_;  // the rows a_i of the stages
  NystromRow solution_row_;                        // the row b
  ClothDynamics dynamics_;
  std::vector<StateDerivative> stage_rate_;  // [stages]: K_i and the powers of stage i
  // The state of the stage being evaluated; after the last stage, the trial solution.
  std::vector<Vec3> stage_position_;  // [particle_count()], m
  std::vector<Vec3> stage_velocity_;  // [particle_count()], m/s
  Work trial_work_;
  // Profile: wall time of the stage sums y + h sum a_ij k_j (with the anchor constraint), and of
  // the solution update y + h sum b_i k_i with, for adaptive methods, the error norm, s.
};

class FixedStepRungeKutta final : public ExplicitRungeKutta {
 public:
  using ExplicitRungeKutta::ExplicitRungeKutta;
  IntegratorKind kind() const override { return IntegratorKind::rk4; }
  StepOutcome step(ClothState& state, double t_limit) override;
};

// RKF45 with error control in the max norm over free particles: a step is accepted when
// max_i |e_i| / (atol + rtol max(|y_i|, |y_new,i|)) <= 1. The max norm, rather than an RMS
// average, keeps a large error at one particle from hiding in a large lattice, so the accepted
// accuracy does not depend on the lattice size. The next step comes from the PI controller of
// integrators/step_control.inc, which the device's RKF45 runs as well.
class AdaptiveRungeKutta final : public ExplicitRungeKutta {
 public:
  AdaptiveRungeKutta(const ClothModel& model, const IntegratorSettings& settings, const ForceOptions& options,
                     const ButcherTableau& tableau);
  IntegratorKind kind() const override { return IntegratorKind::rkf45; }
  StepOutcome step(ClothState& state, double t_limit) override;
  // The step the controller will try next, s.
  double proposed_step() const { return controller_.proposed_step; }
  // The statistics, the next step and the controller's error history.
  void transfer_state(StateArchive& archive) override;

  struct ErrorNorm {
    double value = 0.0;  // max scaled error; NaN if any value was non-finite
    // Where it was largest: the first such particle where value > 1 (or NaN), else the first
    // particle of the first block of 1024 with that value.
    std::uint32_t particle = 0;
  };
  // The error norm of the last trial step (accepted or not).
  const ErrorNorm& last_error() const { return last_error_; }

 private:
  // Forms the trial solution in the stage arrays and, in the same pass, the max norm of the
  // error estimate h sum_i (b_i - b^_i) (V_i, K_i) (combine_solution); where it is above 1, finds
  // the particle.
  ErrorNorm solution_and_error(const ClothState& state, double h);
  // The first trial step: time_step, or initial_adaptive_step() where it is 0.
  double initial_step(const ClothState& state, double t_limit);

  NystromRow error_row_;                     // the row b - b^
  step_control::StepController controller_;  // its proposed step is 0 until the first step
  std::vector<double> block_error_;          // [blocks of 1024 particles]: per-block maxima of the error norm
  ErrorNorm last_error_;
};

// RKF45's automatic first step (time_step 0), from the state and its acceleration, after Hairer,
// Norsett and Wanner (Solving ODEs I, sec. II.4, first half): a step whose Euler increment is 1%
// of the state's own scale. Their refinement with a second-derivative estimate costs another
// evaluation; the controller corrects a misjudged first step within a few steps anyway. Shared
// by the CPU's and the device's RKF45 (gpu/device_integrator.h).
double initial_adaptive_step(const ClothModel& model, const IntegratorSettings& settings, const ClothState& state,
                             std::span<const Vec3> acceleration, double t_limit);

}  // namespace clothsim
