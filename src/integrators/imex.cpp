#include "integrators/imex.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <span>

#include "core/assert.h"
#include "core/parallel.h"
#include "core/step_profile.h"
#include "integrators/error_norm.h"
#include "integrators/explicit_runge_kutta.h"

namespace clothsim {
namespace {

// Particles per block of the error norm's maxima; fixed, so that the result never depends on the
// thread count.
constexpr std::size_t kErrorBlock = 1024;

// The controller's exponents are for an error estimate of order 5 (step_control.inc); this pair's
// is of order 3 (its embedded solution's local error, O(h^3)). The norm raised to 5/3 makes the
// controller's step factors those of a third-order estimate; the test norm <= 1 is unchanged.
constexpr double kControllerPower = 5.0 / 3.0;

// A stage solve that stopped at cg_max_iterations rejects the attempt as if its error norm were
// this: the step shrinks by about half, which also makes the system better conditioned.
constexpr double kUnconvergedError = 32.0;

std::size_t error_blocks(std::size_t n) { return (n + kErrorBlock - 1) / kErrorBlock; }

// The stage solves keep the V-cycle in every solve (with cg_multigrid), not implicit Euler's
// choice by stiffness: block Jacobi would be faster on the paper's material (0.59 against 0.94 s
// for 1 s of paper-fig5), but it moves imex's step sequence through rounding alone, by 2 % on the
// stiff oscillator, where the step control rejects half its attempts; docs/performance.md, "A
// cheaper implicit Euler step".
IntegratorSettings with_vcycle_always(IntegratorSettings settings) {
  settings.cg_vcycle_threshold = 0.0;
  return settings;
}

}  // namespace

AdditiveRungeKutta::AdditiveRungeKutta(const ClothModel& model, const IntegratorSettings& settings,
                                       const ForceOptions& options, const AdditiveTableau& tableau, bool fixed_step)
    : model_(model),
      settings_(settings),
      options_(options),
      tableau_(tableau),
      fixed_step_(fixed_step),
      dynamics_(model, options),
      system_(model, with_vcycle_always(settings), options.threads, profile_),
      controller_(step_control::make_step_controller(settings)),
      revision_(model.revision) {
  CLOTHSIM_ASSERT(tableau.embedded_order > 0, "an adaptive method needs an embedded error estimate");
  CLOTHSIM_ASSERT(settings.cg_max_iterations >= 1, "at least one CG iteration");
  const std::size_t n = model.particle_count();
  const auto stages = static_cast<std::size_t>(tableau.stages);
  stage_rate_.resize(stages);
  for (StateDerivative& rate : stage_rate_) rate.resize(n);
  stage_velocity_.assign(stages, std::vector<Vec3>(n));
  stage_implicit_.assign(stages, std::vector<Vec3>(n));
  stage_position_.resize(n);
  trial_position_.resize(n);
  trial_velocity_.resize(n);
  block_error_.resize(error_blocks(n));
}

std::size_t AdditiveRungeKutta::workspace_bytes() const {
  std::size_t bytes = dynamics_.bytes() + system_.bytes();
  for (std::size_t i = 0; i < stage_rate_.size(); ++i) {
    bytes += stage_rate_[i].bytes() + (stage_velocity_[i].capacity() + stage_implicit_[i].capacity()) * sizeof(Vec3);
  }
  bytes += (stage_position_.capacity() + trial_position_.capacity() + trial_velocity_.capacity()) * sizeof(Vec3);
  return bytes;
}

std::size_t AdditiveRungeKutta::workspace_bytes_for(const LatticeCounts& counts, const IntegratorSettings& settings) {
  const auto stages = static_cast<std::size_t>(kArk324L2SA.stages);
  return BlockSystem::bytes_for(counts, settings) + (3 * stages + 3) * counts.particles * sizeof(Vec3);
}

void AdditiveRungeKutta::begin_step(const ClothState& state) {
  // A model edit between steps (an anchor released, a spring broken or yielded, a live edit)
  // changes which particles are integrated; the Jacobians and masses are read every step anyway.
  if (model_.revision != revision_) {
    system_.update_free();
    revision_ = model_.revision;
  }
  drag_ = (options_.terms & kAirDrag) != 0 ? model_.environment.air_drag : 0.0;
  smallest_mass_ = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < model_.particle_count(); ++p) {
    if (system_.free[p]) smallest_mass_ = std::min(smallest_mass_, model_.particle_mass[p]);
  }
  // Stage 1 is the step's start, for every attempt of the step.
  std::copy(state.velocity.begin(), state.velocity.end(), stage_velocity_[0].begin());
  dynamics_.evaluate(state.time, state.position, state.velocity, stage_rate_[0]);
  system_.compute_jacobians(options_.terms, state.position, state.velocity);
  implicit_rate(0);
  count_evaluations(dynamics_.evaluations());
}

void AdditiveRungeKutta::implicit_rate(int i) {
  const std::vector<Vec3>& velocity = stage_velocity_[static_cast<std::size_t>(i)];
  std::vector<Vec3>& rate = stage_implicit_[static_cast<std::size_t>(i)];
  parallel_for(model_.particle_count(), dynamics_.threads(), [&](std::size_t p) {
    rate[p] = system_.free[p] ? -model_.particle_inverse_mass[p] * system_.damping_product(p, velocity, drag_) : Vec3{};
  });
}

void AdditiveRungeKutta::assemble_system(double h) {
  system_.assemble(options_.terms, tableau_.gamma() * h, 0.0, {}, {});
  system_.setup_preconditioner();
}

void AdditiveRungeKutta::stage_sums(const ClothState& state, double h, int i) {
  StageTimer timer(profile_, StepStage::stage_sums);
  const auto row = static_cast<std::size_t>(i);
  const auto& explicit_row = tableau_.explicit_coefficients[row];
  const auto& implicit_row = tableau_.implicit_coefficients[row];
  parallel_for(model_.particle_count(), dynamics_.threads(), [&](std::size_t p) {
    Vec3 position = state.position[p];
    Vec3 velocity = state.velocity[p];
    for (std::size_t j = 0; j < row; ++j) {
      position += (h * explicit_row[j]) * stage_velocity_[j][p];
      velocity += (h * explicit_row[j]) * stage_rate_[j].velocity_rate[p] +
                  (h * (implicit_row[j] - explicit_row[j])) * stage_implicit_[j][p];
    }
    stage_position_[p] = position;
    system_.rhs[p] = system_.free[p] ? model_.particle_mass[p] * velocity : Vec3{};
  });
}

bool AdditiveRungeKutta::solve_stage(double stage_time, int i) {
  const auto row = static_cast<std::size_t>(i);
  std::vector<Vec3>& unknown = system_.solution;
  std::copy(stage_velocity_[row - 1].begin(), stage_velocity_[row - 1].end(), unknown.begin());
  for (const Anchor& anchor : model_.anchors) {
    stage_position_[anchor.particle] = anchor.path.position(stage_time);
    unknown[anchor.particle] = anchor.path.velocity_at(stage_time);
  }
  // |dV|_2 <= |r|_2 / m_min, since A = M + gamma h D >= M; the relative floor keeps the target
  // above the rounding of b - A u where atol is far below the velocities' own size.
  const double absolute = fixed_step_ ? 0.0 : kSolveFraction * settings_.absolute_tolerance * smallest_mass_;
  const BlockSystem::Solve result = system_.solve(1e-13, absolute, settings_.cg_max_iterations);
  stats_.cg_iterations += static_cast<std::uint64_t>(result.iterations);
  if (!result.converged) ++stats_.cg_unconverged_solves;
  std::swap(unknown, stage_velocity_[row]);
  return result.converged;
}

bool AdditiveRungeKutta::compute_stages(const ClothState& state, double h) {
  assemble_system(h);
  const std::uint64_t iterations_before = stats_.cg_iterations;
  bool converged = true;
  for (int i = 1; i < tableau_.stages; ++i) {
    const double stage_time = state.time + tableau_.nodes[static_cast<std::size_t>(i)] * h;
    stage_sums(state, h, i);
    converged = solve_stage(stage_time, i) && converged;
    if (i + 1 < tableau_.stages) implicit_rate(i);  // the last stage's enters no later stage
    dynamics_.evaluate(stage_time, stage_position_, stage_velocity_[static_cast<std::size_t>(i)],
                       stage_rate_[static_cast<std::size_t>(i)]);
  }
  stats_.cg_max_iterations_in_a_step =
      std::max(stats_.cg_max_iterations_in_a_step, stats_.cg_iterations - iterations_before);
  count_evaluations(dynamics_.evaluations());
  profile_.set(StepStage::forces, dynamics_.seconds());
  return converged;
}

AdditiveRungeKutta::ErrorNorm AdditiveRungeKutta::solution_and_error(const ClothState& state, double h) {
  StageTimer timer(profile_, StepStage::solution_and_error);
  const std::size_t n = model_.particle_count();
  const auto stages = static_cast<std::size_t>(tableau_.stages);
  const double atol = settings_.absolute_tolerance;
  const double rtol = settings_.relative_tolerance;
  std::array<double, kMaxStages> weight{};
  std::array<double, kMaxStages> difference{};
  for (std::size_t j = 0; j < stages; ++j) {
    weight[j] = h * tableau_.weights[j];
    difference[j] = h * (tableau_.weights[j] - tableau_.embedded_weights[j]);
  }
  // x1 = x0 + h sum b_j V_j, v1 = v0 + h sum b_j K_j (b^E = b^I: K_j is the whole rate), and the
  // error estimate with b - b^ in the same pass; per block the largest scaled error's bits.
  const auto particle_error = [&](std::size_t p) {
    Vec3 x1 = state.position[p];
    Vec3 v1 = state.velocity[p];
    Vec3 error_x;
    Vec3 error_v;
    for (std::size_t j = 0; j < stages; ++j) {
      x1 += weight[j] * stage_velocity_[j][p];
      v1 += weight[j] * stage_rate_[j].velocity_rate[p];
      error_x += difference[j] * stage_velocity_[j][p];
      error_v += difference[j] * stage_rate_[j].velocity_rate[p];
    }
    trial_position_[p] = x1;
    trial_velocity_[p] = v1;
    return scaled_error_bits(error_x, error_v, state.position[p], x1, state.velocity[p], v1, atol, rtol,
                             model_.is_anchored(p));
  };
  parallel_for(block_error_.size(), dynamics_.threads(), [&](std::size_t block) {
    std::uint64_t worst = 0;
    const std::size_t end = std::min(n, (block + 1) * kErrorBlock);
    for (std::size_t p = block * kErrorBlock; p < end; ++p) worst = std::max(worst, particle_error(p));
    block_error_[block] = std::bit_cast<double>(worst);
  });
  ErrorNorm norm;
  std::uint64_t worst = 0;
  for (std::size_t block = 0; block < block_error_.size(); ++block) {
    const auto bits = std::bit_cast<std::uint64_t>(block_error_[block]);
    if (bits > worst) {
      worst = bits;
      norm.particle = static_cast<std::uint32_t>(block * kErrorBlock);
    }
  }
  norm.value = std::bit_cast<double>(worst);
  if (!(norm.value <= 1.0)) {
    // The particle with that error, for the step-size floor's diagnosis.
    const std::size_t end = std::min(n, static_cast<std::size_t>(norm.particle) + kErrorBlock);
    for (std::size_t p = norm.particle; p < end; ++p) {
      if (particle_error(p) == worst) {
        norm.particle = static_cast<std::uint32_t>(p);
        break;
      }
    }
  }
  trial_damping_work_ = state.damping_work;
  trial_drag_work_ = state.drag_work;
  trial_anchor_work_ = state.anchor_work;
  for (std::size_t j = 0; j < stages; ++j) {
    trial_damping_work_ += weight[j] * stage_rate_[j].damping_power;
    trial_drag_work_ += weight[j] * stage_rate_[j].drag_power;
    trial_anchor_work_ += weight[j] * stage_rate_[j].anchor_power;
  }
  return norm;
}

void AdditiveRungeKutta::accept(ClothState& state, double h, double t) {
  std::swap(state.position, trial_position_);
  std::swap(state.velocity, trial_velocity_);
  state.damping_work = trial_damping_work_;
  state.drag_work = trial_drag_work_;
  state.anchor_work = trial_anchor_work_;
  state.time = t;
  dynamics_.constrain(t, state.position, state.velocity);
  record_accepted_step(h);
}

StepOutcome AdditiveRungeKutta::step(ClothState& state, double t_limit) {
  CLOTHSIM_ASSERT(t_limit > state.time, "step() needs a limit after the current time");
  begin_step(state);
  if (fixed_step_) {
    bool clipped = false;
    const double h = clip_step(state.time, settings_.time_step, t_limit, clipped);
    compute_stages(state, h);
    solution_and_error(state, h);
    accept(state, h, clipped ? t_limit : state.time + h);
    return {StepStatus::ok, h, 0, false};
  }
  if (controller_.proposed_step <= 0.0) {
    // The first trial step: time_step, or RKF45's automatic one where it is 0.
    const std::span<const Vec3> acceleration = stage_rate_[0].velocity_rate;
    controller_.proposed_step = settings_.time_step > 0.0
                                    ? settings_.time_step
                                    : initial_adaptive_step(model_, settings_, state, acceleration, t_limit);
  }
  controller_.rejected_before = false;
  for (;;) {
    bool clipped = false;
    const double h = clip_step(state.time, std::min(controller_.proposed_step, settings_.max_step), t_limit, clipped);
    if (h < settings_.min_step && !clipped) return {StepStatus::step_underflow, h, 0, false};
    const bool converged = compute_stages(state, h);
    const ErrorNorm error = solution_and_error(state, h);

    const bool non_finite = std::isnan(error.value);
    if (non_finite || error.value > 1.0 || !converged) {
      ++stats_.rejected_steps;
      const double scaled = converged ? std::pow(error.value, kControllerPower) : kUnconvergedError;
      step_control::reject_step(controller_, h, scaled, non_finite);
      if (controller_.proposed_step < settings_.min_step) {
        return {StepStatus::step_underflow, controller_.proposed_step, error.particle, non_finite};
      }
      continue;
    }
    step_control::accept_step(controller_, h, std::pow(error.value, kControllerPower), clipped);
    accept(state, h, clipped ? t_limit : state.time + h);
    return {StepStatus::ok, h, 0, false};
  }
}

void AdditiveRungeKutta::transfer_state(StateArchive& archive) {
  Integrator::transfer_state(archive);
  step_control::transfer_controller(archive, "imex", controller_);
}

}  // namespace clothsim
