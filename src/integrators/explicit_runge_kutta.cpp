#include "integrators/explicit_runge_kutta.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <span>

#include "core/assert.h"
#include "core/multiversion.h"
#include "core/parallel.h"
#include "core/timer.h"

namespace clothsim {
namespace {

// Particles per block of the parallel error-norm reduction; fixed so the result never depends
// on the thread count.
constexpr std::size_t kErrorBlock = 1024;

// Doubles per block of the parallel linear combinations.
constexpr std::size_t kCombinationBlock = 4096;

// out[k] = base[k] + c[0] in[0][k] + c[1] in[1][k] + ..., summed left to right (from 0 when base
// is null), for k in
// [begin, end) of flat double arrays (a Vec3 array is 3n doubles). The number of terms is a
// template parameter so that the term loop unrolls and the loop over k vectorises.
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
    out[k] = sum;
  }
}

// combination_block for a run-time number of terms (0 to kMaxStages), vectorised for the CPU's
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
    default: combination_block<6>(out, base, in, c, begin, end); break;
  }
}

// Linear combination of Vec3 arrays: out = base + sum_t c[t] in[t] (base empty: 0 + ...).
// The same sums, in the same order, as adding c[t] * in[t][p] to a Vec3 term by term, so the
// result is independent of the blocking and of the thread count.
void linear_combination(std::span<Vec3> out, std::span<const Vec3> base, const std::array<const Vec3*, kMaxStages>& in,
                        const std::array<double, kMaxStages>& c, int terms, int threads) {
  const std::size_t size = 3 * out.size();
  double* out_data = &out.data()->x;
  const double* base_data = base.empty() ? nullptr : &base.data()->x;
  std::array<const double*, kMaxStages> flat{};
  for (int t = 0; t < terms; ++t) flat[static_cast<std::size_t>(t)] = &in[static_cast<std::size_t>(t)]->x;
  const std::size_t blocks = (size + kCombinationBlock - 1) / kCombinationBlock;
  parallel_for(blocks, threads, [&](std::size_t block) {
    const std::size_t begin = block * kCombinationBlock;
    const std::size_t end = std::min(size, begin + kCombinationBlock);
    combination_range(out_data, base_data, flat.data(), c.data(), terms, begin, end);
  });
}

// Exponents of the PI step-size controller for an error estimate of order 5 (the embedded
// 4th-order solution's local error): Hairer, Norsett and Wanner's DOPRI5 values, beta = 0.04,
// alpha = 1/5 - 0.75 beta.
constexpr double kControllerBeta = 0.04;
constexpr double kControllerAlpha = 0.2 - 0.75 * kControllerBeta;

}  // namespace

ExplicitRungeKutta::ExplicitRungeKutta(const ClothModel& model, const IntegratorSettings& settings,
                                       const ForceOptions& options, const ButcherTableau& tableau)
    : model_(model), settings_(settings), tableau_(tableau), dynamics_(model, options) {
  const std::size_t n = model.particle_count();
  for (StateDerivative& rate : stage_rate_) rate.resize(n);
  stage_position_.resize(n);
  stage_velocity_.resize(n);
  trial_.position.resize(n);
  trial_.velocity.resize(n);
}

void ExplicitRungeKutta::compute_stages(const ClothState& state, double h) {
  for (int i = 0; i < tableau_.stages; ++i) {
    const auto& a = tableau_.coefficients[static_cast<std::size_t>(i)];
    // Stage state y_i = y + h sum_{j<i} a_ij k_j, over the stages with a non-zero coefficient.
    const double stage_time = state.time + tableau_.nodes[static_cast<std::size_t>(i)] * h;
    {
      ScopedTimer timer(stage_sum_seconds_);
      std::array<double, kMaxStages> coefficient{};
      std::array<const Vec3*, kMaxStages> position_rate{};
      std::array<const Vec3*, kMaxStages> velocity_rate{};
      int terms = 0;
      for (int j = 0; j < i; ++j) {
        const double ha = h * a[static_cast<std::size_t>(j)];
        if (ha == 0.0) continue;
        const auto t = static_cast<std::size_t>(terms++);
        coefficient[t] = ha;
        position_rate[t] = stage_rate_[static_cast<std::size_t>(j)].position_rate.data();
        velocity_rate[t] = stage_rate_[static_cast<std::size_t>(j)].velocity_rate.data();
      }
      linear_combination(stage_position_, state.position, position_rate, coefficient, terms, dynamics_.threads());
      linear_combination(stage_velocity_, state.velocity, velocity_rate, coefficient, terms, dynamics_.threads());
      dynamics_.constrain(stage_time, stage_position_, stage_velocity_);
    }
    dynamics_.evaluate(stage_time, stage_position_, stage_velocity_, stage_rate_[static_cast<std::size_t>(i)]);
  }
  stats_.force_evaluations = dynamics_.evaluations();
  force_seconds_ = dynamics_.seconds();
}

void ExplicitRungeKutta::combine(const ClothState& state, double h, const std::array<double, kMaxStages>& weights,
                                 ClothState& out) {
  ScopedTimer timer(solution_seconds_);
  const int stages = tableau_.stages;
  std::array<double, kMaxStages> coefficient{};
  std::array<const Vec3*, kMaxStages> position_rate{};
  std::array<const Vec3*, kMaxStages> velocity_rate{};
  int terms = 0;
  for (int i = 0; i < stages; ++i) {
    const double hb = h * weights[static_cast<std::size_t>(i)];
    if (hb == 0.0) continue;
    const auto t = static_cast<std::size_t>(terms++);
    coefficient[t] = hb;
    position_rate[t] = stage_rate_[static_cast<std::size_t>(i)].position_rate.data();
    velocity_rate[t] = stage_rate_[static_cast<std::size_t>(i)].velocity_rate.data();
  }
  linear_combination(out.position, state.position, position_rate, coefficient, terms, dynamics_.threads());
  linear_combination(out.velocity, state.velocity, velocity_rate, coefficient, terms, dynamics_.threads());
  out.damping_work = state.damping_work;
  out.drag_work = state.drag_work;
  out.anchor_work = state.anchor_work;
  for (int i = 0; i < stages; ++i) {
    const double hb = h * weights[static_cast<std::size_t>(i)];
    const StateDerivative& rate = stage_rate_[static_cast<std::size_t>(i)];
    out.damping_work += hb * rate.damping_power;
    out.drag_work += hb * rate.drag_power;
    out.anchor_work += hb * rate.anchor_power;
  }
}

std::vector<PhaseTime> ExplicitRungeKutta::phase_times() const {
  std::vector<PhaseTime> phases = {{"stage sums", stage_sum_seconds_}, {"solution update", solution_seconds_}};
  if (kind() == IntegratorKind::rkf45) phases.push_back({"error control", error_seconds_});
  return phases;
}

std::size_t ExplicitRungeKutta::workspace_bytes() const {
  std::size_t bytes = dynamics_.bytes();
  for (const StateDerivative& rate : stage_rate_) bytes += rate.bytes();
  bytes += (stage_position_.capacity() + stage_velocity_.capacity()) * sizeof(Vec3);
  bytes += (trial_.position.capacity() + trial_.velocity.capacity()) * sizeof(Vec3);
  return bytes;
}

void ExplicitRungeKutta::accept(ClothState& state, double h, double t) {
  // Swap rather than copy: trial_ keeps the old buffers as scratch for the next step.
  std::swap(state.position, trial_.position);
  std::swap(state.velocity, trial_.velocity);
  state.damping_work = trial_.damping_work;
  state.drag_work = trial_.drag_work;
  state.anchor_work = trial_.anchor_work;
  state.time = t;
  dynamics_.constrain(t, state.position, state.velocity);
  record_accepted_step(h);
}

StepOutcome FixedStepRungeKutta::step(ClothState& state, double t_limit) {
  CLOTHSIM_ASSERT(t_limit > state.time, "step() needs a limit after the current time");
  bool clipped = false;
  const double h = clip_step(state.time, settings_.time_step, t_limit, clipped);
  compute_stages(state, h);
  combine(state, h, tableau_.weights, trial_);
  for (std::size_t p = 0; p < model_.particle_count(); ++p) {
    if (!is_finite(trial_.position[p]) || !is_finite(trial_.velocity[p])) {
      return {StepStatus::non_finite, h, static_cast<std::uint32_t>(p), true};
    }
  }
  accept(state, h, clipped ? t_limit : state.time + h);
  return {StepStatus::ok, h, 0, false};
}

AdaptiveRungeKutta::AdaptiveRungeKutta(const ClothModel& model, const IntegratorSettings& settings,
                                       const ForceOptions& options, const ButcherTableau& tableau)
    : ExplicitRungeKutta(model, settings, options, tableau) {
  CLOTHSIM_ASSERT(tableau.embedded_order > 0, "an adaptive method needs an embedded error estimate");
  const std::size_t blocks = (model.particle_count() + kErrorBlock - 1) / kErrorBlock;
  block_error_.resize(blocks);
}

namespace {

// The scaled error of one particle as the bit pattern of a non-negative double: for those,
// unsigned integer order is numeric order, with +inf above every finite value and NaN above +inf,
// so a plain integer maximum finds the largest error and lets a non-finite one win, without
// branches. 0 for anchored particles.
[[gnu::always_inline]] inline std::uint64_t scaled_error_bits(const Vec3& error_x, const Vec3& error_v, const Vec3& x0,
                                                              const Vec3& x1, const Vec3& v0, const Vec3& v1,
                                                              double atol, double rtol, bool anchored) {
  const auto ratio = [&](double error, double before, double after) {
    const double scale = atol + rtol * std::max(std::abs(before), std::abs(after));
    // (e - e) and (after - after) are 0 for finite values and NaN otherwise.
    const double ratio_value = std::abs(error) / scale + ((error - error) + (after - after));
    return std::bit_cast<std::uint64_t>(std::abs(ratio_value));
  };
  const std::uint64_t largest =
      std::max(std::max(std::max(ratio(error_x.x, x0.x, x1.x), ratio(error_x.y, x0.y, x1.y)),
                        std::max(ratio(error_x.z, x0.z, x1.z), ratio(error_v.x, v0.x, v1.x))),
               std::max(ratio(error_v.y, v0.y, v1.y), ratio(error_v.z, v0.z, v1.z)));
  return anchored ? 0 : largest;
}

// The largest scaled error bits over particles [begin, end).
CLOTHSIM_MULTIVERSION std::uint64_t largest_error_bits(const Vec3* error_x, const Vec3* error_v, const Vec3* x0,
                                                       const Vec3* x1, const Vec3* v0, const Vec3* v1,
                                                       const std::int32_t* anchor, double atol, double rtol,
                                                       std::size_t begin, std::size_t end) {
  std::uint64_t worst = 0;
  for (std::size_t p = begin; p < end; ++p) {
    worst = std::max(worst, scaled_error_bits(error_x[p], error_v[p], x0[p], x1[p], v0[p], v1[p], atol, rtol,
                                              anchor[p] >= 0));
  }
  return worst;
}

}  // namespace

AdaptiveRungeKutta::ErrorNorm AdaptiveRungeKutta::error_norm(const ClothState& state, double h) {
  ScopedTimer timer(error_seconds_);
  // The error estimate h sum (b_i - b*_i) k_i, into the stage arrays (free until the next step).
  std::array<double, kMaxStages> difference{};
  std::array<const Vec3*, kMaxStages> position_rate{};
  std::array<const Vec3*, kMaxStages> velocity_rate{};
  int terms = 0;
  for (int i = 0; i < tableau_.stages; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double d = h * (tableau_.weights[k] - tableau_.embedded_weights[k]);
    if (d == 0.0) continue;
    const auto t = static_cast<std::size_t>(terms++);
    difference[t] = d;
    position_rate[t] = stage_rate_[k].position_rate.data();
    velocity_rate[t] = stage_rate_[k].velocity_rate.data();
  }
  linear_combination(stage_position_, {}, position_rate, difference, terms, dynamics_.threads());
  linear_combination(stage_velocity_, {}, velocity_rate, difference, terms, dynamics_.threads());

  const double atol = settings_.absolute_tolerance;
  const double rtol = settings_.relative_tolerance;
  const std::size_t n = model_.particle_count();
  const Vec3* error_x = stage_position_.data();
  const Vec3* error_v = stage_velocity_.data();
  const Vec3* x0 = state.position.data();
  const Vec3* x1 = trial_.position.data();
  const Vec3* v0 = state.velocity.data();
  const Vec3* v1 = trial_.velocity.data();
  const std::int32_t* anchor = model_.particle_anchor.data();
  const auto particle_bits = [&](std::size_t p) {
    return scaled_error_bits(error_x[p], error_v[p], x0[p], x1[p], v0[p], v1[p], atol, rtol, anchor[p] >= 0);
  };
  parallel_for(block_error_.size(), dynamics_.threads(), [&](std::size_t block) {
    const std::size_t end = std::min(n, (block + 1) * kErrorBlock);
    block_error_[block] = std::bit_cast<double>(
        largest_error_bits(error_x, error_v, x0, x1, v0, v1, anchor, atol, rtol, block * kErrorBlock, end));
  });
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
  norm.particle = static_cast<std::uint32_t>(worst_block * kErrorBlock);
  if (!(norm.value <= 1.0)) {
    const std::size_t end = std::min(n, (worst_block + 1) * kErrorBlock);
    for (std::size_t p = worst_block * kErrorBlock; p < end; ++p) {
      if (particle_bits(p) == worst) {
        norm.particle = static_cast<std::uint32_t>(p);
        break;
      }
    }
  }
  return norm;
}

// Initial step after Hairer, Norsett and Wanner (Solving ODEs I, sec. II.4, first half): a step
// whose Euler increment is 1% of the state's own scale. Their refinement with a second-derivative
// estimate costs another evaluation; the controller corrects a misjudged first step within a few
// steps anyway.
double AdaptiveRungeKutta::initial_step(const ClothState& state, double t_limit) {
  if (settings_.time_step > 0.0) return settings_.time_step;
  StateDerivative& rate = stage_rate_[0];
  dynamics_.evaluate(state.time, state.position, state.velocity, rate);
  stats_.force_evaluations = dynamics_.evaluations();
  double d0 = 0.0;
  double d1 = 0.0;
  for (std::size_t p = 0; p < model_.particle_count(); ++p) {
    if (model_.is_anchored(p)) continue;
    for (int axis = 0; axis < 3; ++axis) {
      const double sx = settings_.absolute_tolerance + settings_.relative_tolerance * std::abs(state.position[p][axis]);
      const double sv = settings_.absolute_tolerance + settings_.relative_tolerance * std::abs(state.velocity[p][axis]);
      d0 = std::max({d0, std::abs(state.position[p][axis]) / sx, std::abs(state.velocity[p][axis]) / sv});
      d1 = std::max({d1, std::abs(rate.position_rate[p][axis]) / sx, std::abs(rate.velocity_rate[p][axis]) / sv});
    }
  }
  double h = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
  h = std::min({h, settings_.max_step, t_limit - state.time});
  return std::max(h, settings_.min_step);
}

StepOutcome AdaptiveRungeKutta::step(ClothState& state, double t_limit) {
  CLOTHSIM_ASSERT(t_limit > state.time, "step() needs a limit after the current time");
  if (proposed_step_ <= 0.0) proposed_step_ = initial_step(state, t_limit);
  bool rejected_before = false;
  for (;;) {
    bool clipped = false;
    const double h = clip_step(state.time, std::min(proposed_step_, settings_.max_step), t_limit, clipped);
    if (h < settings_.min_step && !clipped) {
      return {StepStatus::step_underflow, h, 0, false};
    }
    compute_stages(state, h);
    combine(state, h, tableau_.weights, trial_);
    const ErrorNorm error = error_norm(state, h);

    if (std::isnan(error.value) || error.value > 1.0) {
      // Reject: shrink by the optimal factor for this error, never by more than max_shrink.
      ++stats_.rejected_steps;
      const double factor = std::isnan(error.value)
                                ? settings_.max_shrink
                                : std::max(settings_.max_shrink, settings_.safety * std::pow(error.value, -0.2));
      proposed_step_ = h * std::min(1.0, factor);
      rejected_before = true;
      if (proposed_step_ < settings_.min_step) {
        return {StepStatus::step_underflow, proposed_step_, error.particle, std::isnan(error.value)};
      }
      continue;
    }

    // Accept, and propose the next step with the PI controller. After a rejection the step may
    // not grow (Hairer's rule), which stops a rejection cycle at the stability limit.
    const double bounded_error = std::max(error.value, 1e-10);
    double factor = settings_.safety * std::pow(bounded_error, -kControllerAlpha) *
                    std::pow(previous_error_, kControllerBeta);
    factor = std::clamp(factor, settings_.max_shrink, settings_.max_growth);
    if (rejected_before) factor = std::min(factor, 1.0);
    previous_error_ = std::max(error.value, 1e-4);
    const double next = h * factor;
    // A step clipped to land on t_limit says little about the step the dynamics allow: keep the
    // larger of the old proposal and the new one.
    proposed_step_ = clipped ? std::max(next, proposed_step_) : next;
    accept(state, h, clipped ? t_limit : state.time + h);
    return {StepStatus::ok, h, 0, false};
  }
}

void AdaptiveRungeKutta::transfer_state(StateArchive& archive) {
  Integrator::transfer_state(archive);
  archive.value("rkf45.proposed_step", proposed_step_);
  archive.value("rkf45.previous_error", previous_error_);
}

}  // namespace clothsim
