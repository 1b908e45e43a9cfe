#include "integrators/explicit_runge_kutta.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "core/assert.h"
#include "core/multiversion.h"
#include "core/parallel.h"
#include "core/step_profile.h"
#include "integrators/error_norm.h"

namespace clothsim {
namespace {

// Particles per block of the solution pass (the trial solution and, under error control, the
// largest scaled error of its estimate); fixed so that the per-block maxima, and so the result,
// never depend on the thread count.
constexpr std::size_t kSolutionBlock = 1024;
// Particles per piece of a block whose trial solution and error estimate are formed one after the
// other: the piece's accelerations (s x 6 KiB), state and trial solution are still in the core's
// cache when its error estimate (on the stack, 2 x 6 KiB) reads them again.
constexpr std::size_t kSolutionPiece = 256;

// Doubles per block of the parallel stage sums.
constexpr std::size_t kCombinationBlock = 4096;

// Terms of a combination: the velocity and one acceleration per stage (Nystrom form).
constexpr int kMaxTerms = kMaxStages + 1;
using Terms = std::array<const double*, kMaxTerms>;
using Coefficients = std::array<double, kMaxTerms>;

// out[k - begin] = base[k] + c[0] in[0][k] + c[1] in[1][k] + ..., summed left to right (from 0
// when base is null), for k in [begin, end) of flat double arrays (a Vec3 array is 3n doubles).
// The number of terms is a template parameter so that the term loop unrolls and the loop over k
// vectorises.
template <int kTerms>
[[gnu::always_inline]] inline void combination_block(double* __restrict out, const double* __restrict base,
                                                     const double* const* in, const double* c, std::size_t begin,
                                                     std::size_t end) {
  const double* __restrict term[kTerms > 0 ? kTerms : 1];
  double coefficient[kTerms > 0 ? kTerms : 1];
  for (int t = 0; t < kTerms; ++t) {
    term[t] = in[t];
    coefficient[t] = c[t];
  }
#pragma GCC ivdep
  for (std::size_t k = begin; k < end; ++k) {
    double sum = base != nullptr ? base[k] : 0.0;
    for (int t = 0; t < kTerms; ++t) sum += coefficient[t] * term[t][k];
    out[k - begin] = sum;
  }
}

// combination_block for a run-time number of terms (0 to kMaxTerms), vectorised for the CPU's
// widest vectors (core/multiversion.h).
CLOTHSIM_MULTIVERSION void combination_range(double* out, const double* base, const double* const* in, const double* c,
                                             int terms, std::size_t begin, std::size_t end) {
  switch (terms) {
    case 0: combination_block<0>(out, base, in, c, begin, end); break;
    case 1: combination_block<1>(out, base, in, c, begin, end); break;
    case 2: combination_block<2>(out, base, in, c, begin, end); break;
    case 3: combination_block<3>(out, base, in, c, begin, end); break;
    case 4: combination_block<4>(out, base, in, c, begin, end); break;
    case 5: combination_block<5>(out, base, in, c, begin, end); break;
    case 6: combination_block<6>(out, base, in, c, begin, end); break;
    default: combination_block<7>(out, base, in, c, begin, end); break;
  }
  static_assert(kMaxTerms == 7, "one case per term count");
}

// A row's combination h sum_i w_i (V_i, K_i) in Nystrom form as two lists of terms: positions
// h (sum w) v + h^2 sum_l position_l K_l, velocities h sum_l w_l K_l. Zero coefficients are
// skipped (an unused stage, Fehlberg's second one in b).
struct RowTerms {
  Terms position_term{};
  Coefficients position_coefficient{};
  int position_terms = 0;
  Terms velocity_term{};
  Coefficients velocity_coefficient{};
  int velocity_terms = 0;
};

RowTerms row_terms(const NystromRow& row, double h, const Vec3* velocity, const std::vector<StateDerivative>& rates) {
  RowTerms terms;
  if (row.velocity_sum != 0.0) {
    terms.position_coefficient[0] = h * row.velocity_sum;
    terms.position_term[0] = &velocity->x;
    terms.position_terms = 1;
  }
  for (std::size_t l = 0; l < rates.size(); ++l) {
    const double* acceleration = &rates[l].velocity_rate.data()->x;
    if (row.position[l] != 0.0) {
      const auto t = static_cast<std::size_t>(terms.position_terms++);
      terms.position_coefficient[t] = h * h * row.position[l];
      terms.position_term[t] = acceleration;
    }
    if (row.velocity[l] != 0.0) {
      const auto t = static_cast<std::size_t>(terms.velocity_terms++);
      terms.velocity_coefficient[t] = h * row.velocity[l];
      terms.velocity_term[t] = acceleration;
    }
  }
  return terms;
}

// Both halves of a row over the flat doubles k in [begin, end) (particles begin / 3 to end / 3):
// position_out[k - begin] = base_position[k] + the position terms, velocity_out[k - begin] =
// base_velocity[k] + the velocity terms (null bases: 0 + ...). One pass over the range for both,
// so the terms' accelerations, which the two share, are read from cache the second time. Each
// value is the same sum, in the same order, as adding c[t] * in[t][p] to a Vec3 term by term,
// whatever the range: the result is independent of the blocking and of the thread count.
void combine_range(const RowTerms& terms, const double* base_position, const double* base_velocity,
                   double* position_out, double* velocity_out, std::size_t begin, std::size_t end) {
  combination_range(position_out, base_position, terms.position_term.data(), terms.position_coefficient.data(),
                    terms.position_terms, begin, end);
  combination_range(velocity_out, base_velocity, terms.velocity_term.data(), terms.velocity_coefficient.data(),
                    terms.velocity_terms, begin, end);
}

// The largest scaled error bits over particles [begin, end).
CLOTHSIM_MULTIVERSION std::uint64_t largest_error_bits(const Vec3* error_x, const Vec3* error_v, const Vec3* x0,
                                                       const Vec3* x1, const Vec3* v0, const Vec3* v1,
                                                       const std::int32_t* anchor, double atol, double rtol,
                                                       std::size_t begin, std::size_t end) {
  std::uint64_t worst = 0;
  for (std::size_t p = begin; p < end; ++p) {
    worst = std::max(worst,
                     scaled_error_bits(error_x[p], error_v[p], x0[p], x1[p], v0[p], v1[p], atol, rtol, anchor[p] >= 0));
  }
  return worst;
}

}  // namespace

ExplicitRungeKutta::ExplicitRungeKutta(const ClothModel& model, const IntegratorSettings& settings,
                                       const ForceOptions& options, const ButcherTableau& tableau)
    : model_(model), settings_(settings), tableau_(tableau), dynamics_(model, options) {
  for (int i = 0; i < tableau_.stages; ++i) {
    stage_rows_[static_cast<std::size_t>(i)] =
        nystrom_row(tableau_, tableau_.coefficients[static_cast<std::size_t>(i)]);
  }
  solution_row_ = nystrom_row(tableau_, tableau_.weights);
  const std::size_t n = model.particle_count();
  stage_rate_.resize(static_cast<std::size_t>(tableau_.stages));
  for (StateDerivative& rate : stage_rate_) rate.resize(n);
  stage_position_.resize(n);
  stage_velocity_.resize(n);
}

NystromRow nystrom_row(const ButcherTableau& tableau, const std::array<double, kMaxStages>& weights) {
  NystromRow row;
  for (int i = 0; i < tableau.stages; ++i) {
    const double w = weights[static_cast<std::size_t>(i)];
    row.velocity_sum += w;
    row.velocity[static_cast<std::size_t>(i)] = w;
    for (int l = 0; l < i; ++l) {
      row.position[static_cast<std::size_t>(l)] +=
          w * tableau.coefficients[static_cast<std::size_t>(i)][static_cast<std::size_t>(l)];
    }
  }
  return row;
}

void ExplicitRungeKutta::combine_stage(const NystromRow& row, double h, const ClothState& state) {
  // One parallel sweep writes both the stage positions and the stage velocities, block by
  // block: one fork and join per stage instead of one per array, and each block's accelerations
  // (shared by both rows' terms) are still in cache for the velocities.
  const RowTerms terms = row_terms(row, h, state.velocity.data(), stage_rate_);
  const double* base_position = &state.position.data()->x;
  const double* base_velocity = &state.velocity.data()->x;
  double* position_out = &stage_position_.data()->x;
  double* velocity_out = &stage_velocity_.data()->x;
  const std::size_t size = 3 * model_.particle_count();
  const std::size_t blocks = (size + kCombinationBlock - 1) / kCombinationBlock;
  parallel_for(blocks, dynamics_.threads(), [&](std::size_t block) {
    const std::size_t begin = block * kCombinationBlock;
    const std::size_t end = std::min(size, begin + kCombinationBlock);
    combine_range(terms, base_position, base_velocity, position_out + begin, velocity_out + begin, begin, end);
  });
}

void ExplicitRungeKutta::compute_stages(const ClothState& state, double h) {
  for (int i = 0; i < tableau_.stages; ++i) {
    const auto k = static_cast<std::size_t>(i);
    // Stage state y_i = y + h sum_{j<i} a_ij (V_j, K_j), over the terms with a non-zero coefficient.
    const double stage_time = state.time + tableau_.nodes[k] * h;
    {
      StageTimer timer(profile_, StepStage::stage_sums);
      combine_stage(stage_rows_[k], h, state);
      dynamics_.constrain(stage_time, stage_position_, stage_velocity_);
    }
    dynamics_.evaluate(stage_time, stage_position_, stage_velocity_, stage_rate_[k]);
  }
  count_evaluations(dynamics_.evaluations());
  profile_.set(StepStage::forces, dynamics_.seconds());
}

void ExplicitRungeKutta::combine_solution(const ClothState& state, double h, const NystromRow* error_row,
                                          std::span<double> block_error) {
  const std::size_t n = model_.particle_count();
  CLOTHSIM_ASSERT(error_row == nullptr || block_error.size() == (n + kSolutionBlock - 1) / kSolutionBlock,
                  "one error maximum per block of the solution pass");
  const RowTerms solution = row_terms(solution_row_, h, state.velocity.data(), stage_rate_);
  const RowTerms error =
      error_row != nullptr ? row_terms(*error_row, h, state.velocity.data(), stage_rate_) : RowTerms{};
  const double atol = settings_.absolute_tolerance;
  const double rtol = settings_.relative_tolerance;
  const Vec3* x0 = state.position.data();
  const Vec3* v0 = state.velocity.data();
  Vec3* x1 = stage_position_.data();
  Vec3* v1 = stage_velocity_.data();
  const std::int32_t* anchor = model_.particle_anchor.data();
  const std::size_t blocks = (n + kSolutionBlock - 1) / kSolutionBlock;
  // Piece by piece, the trial solution y + h sum b_i (V_i, K_i) goes into the stage arrays, and
  // then, from the same accelerations and the solution just written, while both are in cache,
  // the error estimate h sum (b_i - b^_i) (V_i, K_i) and its largest scaled error. Separate
  // sweeps (positions, velocities, then the error) read the accelerations from memory three
  // times and forked and joined three times.
  parallel_for(blocks, dynamics_.threads(), [&](std::size_t block) {
    std::array<Vec3, kSolutionPiece> error_x;
    std::array<Vec3, kSolutionPiece> error_v;
    std::uint64_t worst = 0;
    const std::size_t block_end = std::min(n, (block + 1) * kSolutionBlock);
    for (std::size_t begin = block * kSolutionBlock; begin < block_end; begin += kSolutionPiece) {
      const std::size_t end = std::min(block_end, begin + kSolutionPiece);
      combine_range(solution, &x0->x, &v0->x, &x1[begin].x, &v1[begin].x, 3 * begin, 3 * end);
      if (error_row == nullptr) continue;
      combine_range(error, nullptr, nullptr, &error_x.data()->x, &error_v.data()->x, 3 * begin, 3 * end);
      worst = std::max(worst, largest_error_bits(error_x.data(), error_v.data(), x0 + begin, x1 + begin, v0 + begin,
                                                 v1 + begin, anchor + begin, atol, rtol, 0, end - begin));
    }
    if (error_row != nullptr) block_error[block] = std::bit_cast<double>(worst);
  });
  trial_work_ = {state.damping_work, state.drag_work, state.anchor_work};
  for (std::size_t i = 0; i < stage_rate_.size(); ++i) {
    const double hb = h * tableau_.weights[i];
    const StateDerivative& rate = stage_rate_[i];
    trial_work_.damping += hb * rate.damping_power;
    trial_work_.drag += hb * rate.drag_power;
    trial_work_.anchor += hb * rate.anchor_power;
  }
}

std::optional<double> ExplicitRungeKutta::float32_acceleration_error(const ClothState& state) {
  if (!dynamics_.runs_float32()) return std::nullopt;
  const double rounding =
      dynamics_.float32_rounding(state.time, state.position, state.velocity, stage_rate_[0], stage_rate_[1]);
  count_evaluations(dynamics_.evaluations());
  profile_.set(StepStage::forces, dynamics_.seconds());
  return rounding;
}

void ExplicitRungeKutta::set_force_precision(Precision precision) {
  if (dynamics_.runs_float32()) dynamics_.set_precision(precision);
}

std::size_t ExplicitRungeKutta::workspace_bytes() const {
  std::size_t bytes = dynamics_.bytes();
  for (const StateDerivative& rate : stage_rate_) bytes += rate.bytes();
  bytes += (stage_position_.capacity() + stage_velocity_.capacity()) * sizeof(Vec3);
  return bytes;
}

std::size_t ExplicitRungeKutta::workspace_bytes_for(int stages, std::size_t particles) {
  // The accelerations of every stage, and the stage (then trial) positions and velocities.
  return static_cast<std::size_t>(stages) * StateDerivative::bytes_for(particles) +
         2 * particles * sizeof(decltype(stage_position_)::value_type);
}

void ExplicitRungeKutta::accept(ClothState& state, double h, double t) {
  // Swap rather than copy: the stage arrays keep the old buffers as scratch for the next step.
  std::swap(state.position, stage_position_);
  std::swap(state.velocity, stage_velocity_);
  state.damping_work = trial_work_.damping;
  state.drag_work = trial_work_.drag;
  state.anchor_work = trial_work_.anchor;
  state.time = t;
  dynamics_.constrain(t, state.position, state.velocity);
  record_accepted_step(h);
}

StepOutcome FixedStepRungeKutta::step(ClothState& state, double t_limit) {
  CLOTHSIM_ASSERT(t_limit > state.time, "step() needs a limit after the current time");
  bool clipped = false;
  const double h = clip_step(state.time, settings_.time_step, t_limit, clipped);
  compute_stages(state, h);
  {
    StageTimer timer(profile_, StepStage::solution_update);
    combine_solution(state, h);
  }
  for (std::size_t p = 0; p < model_.particle_count(); ++p) {
    if (!is_finite(stage_position_[p]) || !is_finite(stage_velocity_[p])) {
      return {StepStatus::non_finite, h, static_cast<std::uint32_t>(p), true};
    }
  }
  accept(state, h, clipped ? t_limit : state.time + h);
  return {StepStatus::ok, h, 0, false};
}

AdaptiveRungeKutta::AdaptiveRungeKutta(const ClothModel& model, const IntegratorSettings& settings,
                                       const ForceOptions& options, const ButcherTableau& tableau)
    : ExplicitRungeKutta(model, settings, options, tableau), controller_(step_control::make_step_controller(settings)) {
  CLOTHSIM_ASSERT(tableau.embedded_order > 0, "an adaptive method needs an embedded error estimate");
  std::array<double, kMaxStages> difference{};
  for (std::size_t i = 0; i < difference.size(); ++i) difference[i] = tableau.weights[i] - tableau.embedded_weights[i];
  error_row_ = nystrom_row(tableau, difference);
  const std::size_t blocks = (model.particle_count() + kSolutionBlock - 1) / kSolutionBlock;
  block_error_.resize(blocks);
}

AdaptiveRungeKutta::ErrorNorm AdaptiveRungeKutta::solution_and_error(const ClothState& state, double h) {
  // With error control the solution and its error norm are one pass, timed as one.
  StageTimer timer(profile_, StepStage::solution_and_error);
  combine_solution(state, h, &error_row_, block_error_);
  // The first block with the largest error, and (only when the step fails, where it is reported)
  // the first particle in it with that error.
  std::uint64_t worst = 0;
  std::size_t worst_block = 0;
  for (std::size_t block = 0; block < block_error_.size(); ++block) {
    const auto bits = std::bit_cast<std::uint64_t>(block_error_[block]);
    if (bits > worst) {
      worst = bits;
      worst_block = block;
    }
  }
  ErrorNorm norm;
  norm.value = std::bit_cast<double>(worst);
  norm.particle = static_cast<std::uint32_t>(worst_block * kSolutionBlock);
  if (!(norm.value <= 1.0)) {
    const double atol = settings_.absolute_tolerance;
    const double rtol = settings_.relative_tolerance;
    const Vec3* x0 = state.position.data();
    const Vec3* x1 = stage_position_.data();
    const Vec3* v0 = state.velocity.data();
    const Vec3* v1 = stage_velocity_.data();
    const RowTerms error = row_terms(error_row_, h, v0, stage_rate_);
    const std::size_t block_end = std::min(model_.particle_count(), (worst_block + 1) * kSolutionBlock);
    for (std::size_t p = worst_block * kSolutionBlock; p < block_end; ++p) {
      Vec3 error_x;
      Vec3 error_v;
      combine_range(error, nullptr, nullptr, &error_x.x, &error_v.x, 3 * p, 3 * p + 3);
      if (scaled_error_bits(error_x, error_v, x0[p], x1[p], v0[p], v1[p], atol, rtol, model_.is_anchored(p)) == worst) {
        norm.particle = static_cast<std::uint32_t>(p);
        break;
      }
    }
  }
  last_error_ = norm;
  return norm;
}

double initial_adaptive_step(const ClothModel& model, const IntegratorSettings& settings, const ClothState& state,
                             std::span<const Vec3> acceleration, double t_limit) {
  double d0 = 0.0;
  double d1 = 0.0;
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    if (model.is_anchored(p)) continue;
    for (int axis = 0; axis < 3; ++axis) {
      const double sx = settings.absolute_tolerance + settings.relative_tolerance * std::abs(state.position[p][axis]);
      const double sv = settings.absolute_tolerance + settings.relative_tolerance * std::abs(state.velocity[p][axis]);
      d0 = std::max({d0, std::abs(state.position[p][axis]) / sx, std::abs(state.velocity[p][axis]) / sv});
      // The position rate is the velocity.
      d1 = std::max({d1, std::abs(state.velocity[p][axis]) / sx, std::abs(acceleration[p][axis]) / sv});
    }
  }
  double h = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
  h = std::min({h, settings.max_step, t_limit - state.time});
  return std::max(h, settings.min_step);
}

double AdaptiveRungeKutta::initial_step(const ClothState& state, double t_limit) {
  if (settings_.time_step > 0.0) return settings_.time_step;
  StateDerivative& rate = stage_rate_[0];
  dynamics_.evaluate(state.time, state.position, state.velocity, rate);
  count_evaluations(dynamics_.evaluations());
  return initial_adaptive_step(model_, settings_, state, rate.velocity_rate, t_limit);
}

StepOutcome AdaptiveRungeKutta::step(ClothState& state, double t_limit) {
  CLOTHSIM_ASSERT(t_limit > state.time, "step() needs a limit after the current time");
  if (controller_.proposed_step <= 0.0) controller_.proposed_step = initial_step(state, t_limit);
  controller_.rejected_before = false;
  for (;;) {
    bool clipped = false;
    const double h = clip_step(state.time, std::min(controller_.proposed_step, settings_.max_step), t_limit, clipped);
    if (h < settings_.min_step && !clipped) {
      return {StepStatus::step_underflow, h, 0, false};
    }
    compute_stages(state, h);
    const ErrorNorm error = solution_and_error(state, h);

    const bool non_finite = std::isnan(error.value);
    if (non_finite || error.value > 1.0) {
      ++stats_.rejected_steps;
      step_control::reject_step(controller_, h, error.value, non_finite);
      if (controller_.proposed_step < settings_.min_step) {
        return {StepStatus::step_underflow, controller_.proposed_step, error.particle, non_finite};
      }
      continue;
    }
    step_control::accept_step(controller_, h, error.value, clipped);
    accept(state, h, clipped ? t_limit : state.time + h);
    return {StepStatus::ok, h, 0, false};
  }
}

void AdaptiveRungeKutta::transfer_state(StateArchive& archive) {
  Integrator::transfer_state(archive);
  step_control::transfer_controller(archive, "rkf45", controller_);
}

}  // namespace clothsim
