// Explicit Runge-Kutta integrators driven by a Butcher tableau.
//
// ExplicitRungeKutta computes the stages of one trial step of size h from the current state;
// AdaptiveRungeKutta wraps it in step-size control (RKF45), FixedStepRungeKutta takes steps of
// the configured size (RK4, or any tableau in tests). All scratch arrays are allocated in the
// constructor.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "integrators/dynamics.h"
#include "integrators/integrator.h"
#include "integrators/tableau.h"

namespace clothsim {

class ExplicitRungeKutta : public Integrator {
 public:
  ExplicitRungeKutta(const ClothModel& model, const IntegratorSettings& settings, const ForceOptions& options,
                     const ButcherTableau& tableau);
  const ButcherTableau& tableau() const { return tableau_; }
  std::vector<PhaseTime> phase_times() const override;
  std::size_t workspace_bytes() const override;

 protected:
  // Evaluates every stage of a step of size h from `state`.
  void compute_stages(const ClothState& state, double h);
  // Writes state + h sum_i weights_i k_i into `out` (positions, velocities and work integrals).
  void combine(const ClothState& state, double h, const std::array<double, kMaxStages>& weights, ClothState& out);
  // Accepts `trial` as the new state at time t: exact anchor positions, statistics.
  void accept(ClothState& state, double h, double t);

  const ClothModel& model_;
  IntegratorSettings settings_;
  ButcherTableau tableau_;
  ClothDynamics dynamics_;
  std::array<StateDerivative, kMaxStages> stage_rate_;
  std::vector<Vec3> stage_position_;  // [particle_count()]
  std::vector<Vec3> stage_velocity_;  // [particle_count()]
  ClothState trial_;                  // the propagated solution of the current trial step
  // Profile: wall time of the stage sums y + h sum a_ij k_j (with the anchor constraint), of the
  // solution update y + h sum b_i k_i, and of the error norm (adaptive methods), s.
  double stage_sum_seconds_ = 0.0;
  double solution_seconds_ = 0.0;
  double error_seconds_ = 0.0;
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
// accuracy does not depend on the lattice size. The next step comes from a PI controller
// (Gustafsson; Hairer and Wanner's DOPRI5 settings), which avoids the step-size oscillation a
// plain controller shows on stiff problems such as the paper's heavily damped springs.
class AdaptiveRungeKutta final : public ExplicitRungeKutta {
 public:
  AdaptiveRungeKutta(const ClothModel& model, const IntegratorSettings& settings, const ForceOptions& options,
                     const ButcherTableau& tableau);
  IntegratorKind kind() const override { return IntegratorKind::rkf45; }
  StepOutcome step(ClothState& state, double t_limit) override;
  // The step the controller will try next, s.
  double proposed_step() const { return proposed_step_; }
  // The statistics, the next step and the controller's error history.
  void transfer_state(StateArchive& archive) override;

 private:
  struct ErrorNorm {
    double value = 0.0;           // max scaled error; NaN if any value was non-finite
    std::uint32_t particle = 0;   // where it was largest
  };
  ErrorNorm error_norm(const ClothState& state, double h);
  double initial_step(const ClothState& state, double t_limit);

  double proposed_step_ = 0.0;  // 0 until the first step
  double previous_error_ = 1e-4;
  std::vector<double> block_error_;  // per-block maxima of the error norm
};

}  // namespace clothsim
