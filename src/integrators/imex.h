// The adaptive IMEX integrator (`--integrator imex`): an additive Runge-Kutta pair with an
// embedded error estimate, Kennedy and Carpenter's ARK3(2)4L[2]SA (tableau.h), after their
// "Additive Runge-Kutta schemes for convection-diffusion-reaction equations" (Appl. Numer. Math.
// 44, 2003). The paper's material is stiff through its damping only (rates of 4,000 to 5,800 per
// second against elastic frequencies near 200 rad/s: issue 25), so the damping is the implicit
// part and everything else the explicit one, which lets the step follow the elastic motion.
//
// The split. With y = (x, v), f_I(y) = (0, -M^-1 D v), D = C0 + drag I, C0 = -df/dv the damping
// Jacobian at the step's start (forces/element_jacobian.h; exact, the damping is linear in v),
// and f_E = f - f_I: positions, elastic forces, gravity and whatever part of the damping D does
// not capture once x has moved. Any split fixed within a step keeps the pair's order. The
// positions being explicit, each stage's X_i is known before its solve, and the implicit stage
//   (M + gamma h D) V_i = M v0 + h sum_{j<i} (a^E_ij M K_j + (a^I_ij - a^E_ij) M KI_j),
// K_j = f(X_j, V_j) / m the whole stage acceleration and KI_j = -M^-1 D V_j, is one linear
// symmetric positive definite system: no Newton iteration. It is the BlockSystem of implicit
// Euler (block_system.h) with the stiffness scale 0: assembled and preconditioned once per
// attempt, solved three times from the previous stage's velocities. CG stops when the residual
// bounds the stage velocity's error by kSolveFraction atol (A >= M, so |dV| <= |r| / m_min).
//
// Error control, controller, anchors and work as RKF45's (explicit_runge_kutta.h): the max norm
// of error_norm.h over h sum (b_i - b^_i) (V_i, K_i); the PI controller of step_control.inc, fed
// the norm to the power 5/3 because its exponents are for a fifth-order estimate and this one
// is third order; anchored particles on their paths at every stage; the work integrals
// h sum b_i P_i with the powers of every stage's full force evaluation, so the energy balance
// measures the integration error only. 4 force evaluations per attempt, 3 solves.
#pragma once

#include <vector>

#include "integrators/block_system.h"
#include "integrators/dynamics.h"
#include "integrators/integrator.h"
#include "integrators/step_control.h"
#include "integrators/tableau.h"

namespace clothsim {

class AdditiveRungeKutta final : public Integrator {
 public:
  // `fixed_step`: steps of time_step with no error control, and stage solves to rounding (the
  // convergence tests measure the orders of the pair's rows this way).
  AdditiveRungeKutta(const ClothModel& model, const IntegratorSettings& settings, const ForceOptions& options,
                     const AdditiveTableau& tableau = kArk324L2SA, bool fixed_step = false);
  IntegratorKind kind() const override { return IntegratorKind::imex; }
  StepOutcome step(ClothState& state, double t_limit) override;
  std::size_t workspace_bytes() const override;
  // workspace_bytes() on the lattice build_lattice() makes with `counts`, besides the force
  // buffers (sim/memory_estimate.h).
  static std::size_t workspace_bytes_for(const LatticeCounts& counts, const IntegratorSettings& settings);
  // The step the controller will try next, s.
  double proposed_step() const { return controller_.proposed_step; }
  // The statistics, the next step and the controller's error history.
  void transfer_state(StateArchive& archive) override;

  // The fraction of atol that a stage solve's error may reach.
  static constexpr double kSolveFraction = 0.01;

 private:
  struct ErrorNorm {
    double value = 0.0;  // max scaled error; NaN if any value was non-finite
    std::uint32_t particle = 0;
  };
  // The step's start: the free set after model edits, the rate and the damping Jacobian at y_n.
  void begin_step(const ClothState& state);
  // The implicit system M + gamma h D and its preconditioner for a trial step h.
  void assemble_system(double h);
  // Stages 2..s of a trial step h from `state`; false when a solve stopped at cg_max_iterations.
  bool compute_stages(const ClothState& state, double h);
  // Stage i's positions x0 + h sum_j a^E_ij V_j (anchors on their paths) and its right-hand side.
  void stage_sums(const ClothState& state, double h, int i);
  // Solves stage i's system from stage i-1's velocities; returns whether CG converged.
  bool solve_stage(double stage_time, int i);
  // KI_i = -M^-1 D V_i.
  void implicit_rate(int i);
  // The trial solution into trial_* and the max norm of its error estimate.
  ErrorNorm solution_and_error(const ClothState& state, double h);
  void accept(ClothState& state, double h, double t);

  const ClothModel& model_;
  IntegratorSettings settings_;
  ForceOptions options_;
  AdditiveTableau tableau_;
  bool fixed_step_ = false;
  ClothDynamics dynamics_;
  BlockSystem system_;
  step_control::StepController controller_;  // its proposed step is 0 until the first step
  std::uint64_t revision_ = 0;               // model revision the free set was made for
  double drag_ = 0.0;                        // kg/s, the implicit part's drag coefficient
  double smallest_mass_ = 0.0;               // kg, over the free particles

  std::vector<StateDerivative> stage_rate_;          // [stages]: K_i and the powers of stage i
  std::vector<std::vector<Vec3>> stage_velocity_;    // [stages][particle_count()]: V_i, m/s
  std::vector<std::vector<Vec3>> stage_implicit_;    // [stages][particle_count()]: KI_i, m/s^2
  std::vector<Vec3> stage_position_;                 // [particle_count()]: X_i of the stage being formed, m
  std::vector<Vec3> trial_position_;                 // [particle_count()], m
  std::vector<Vec3> trial_velocity_;                 // [particle_count()], m/s
  std::vector<double> block_error_;                  // [blocks of 1024 particles]: error-norm maxima
  double trial_damping_work_ = 0.0;
  double trial_drag_work_ = 0.0;
  double trial_anchor_work_ = 0.0;
};

}  // namespace clothsim
