#include "integrators/implicit_euler.h"

#include <algorithm>
#include <cmath>

#include "core/assert.h"
#include "core/parallel.h"
#include "core/timer.h"
#include "integrators/dynamics.h"

namespace clothsim {
namespace {

// Particles per block of the deterministic reductions; fixed, never derived from the thread count.
constexpr std::size_t kReductionBlock = 1024;

std::size_t block_count(std::size_t n) { return (n + kReductionBlock - 1) / kReductionBlock; }

// Sums body(begin, end) -> std::array<double, 3> over fixed blocks of [0, n), the blocks in
// parallel and their results added in block order: the same bits for any thread count.
template <typename Body>
std::array<double, 3> blocked_sums(std::size_t n, int threads, std::vector<double>& a, std::vector<double>& b,
                                   std::vector<double>& c, Body&& body) {
  const std::size_t blocks = block_count(n);
  parallel_for(blocks, threads, [&](std::size_t block) {
    const std::size_t begin = block * kReductionBlock;
    const std::array<double, 3> sums = body(begin, std::min(n, begin + kReductionBlock));
    a[block] = sums[0];
    b[block] = sums[1];
    c[block] = sums[2];
  });
  std::array<double, 3> total{};
  for (std::size_t block = 0; block < blocks; ++block) {
    total[0] += a[block];
    total[1] += b[block];
    total[2] += c[block];
  }
  return total;
}

std::uint32_t find_block(const std::vector<std::uint32_t>& row_offset, const std::vector<std::uint32_t>& column,
                         std::uint32_t row, std::uint32_t col) {
  const auto first = column.begin() + row_offset[row];
  const auto last = column.begin() + row_offset[row + 1];
  const auto it = std::lower_bound(first, last, col);
  CLOTHSIM_ASSERT(it != last && *it == col, "every element pair has a block");
  return static_cast<std::uint32_t>(it - column.begin());
}

}  // namespace

ImplicitEuler::ImplicitEuler(const ClothModel& model, const IntegratorSettings& settings, const ForceOptions& options)
    : model_(model), settings_(settings), options_(options), threads_(options.threads) {
  CLOTHSIM_ASSERT(settings.cg_max_iterations >= 1, "at least one CG iteration");
  const std::size_t n = model.particle_count();
  buffers_.resize(model);
  force_.resize(n);
  evaluated_position_.resize(n);
  evaluated_velocity_.resize(n);
  connector_jacobian_.resize(model.connector_count());
  radial_jacobian_.resize(model.radial_count());

  // Block structure: each particle's neighbours through any element, and itself, ascending.
  std::vector<std::vector<std::uint32_t>> neighbours(n);
  for (std::size_t p = 0; p < n; ++p) neighbours[p].push_back(static_cast<std::uint32_t>(p));
  for (const auto& [a, b] : model.connector_particles) {
    neighbours[a].push_back(b);
    neighbours[b].push_back(a);
  }
  for (const auto& particles : model.radial_particles) {
    for (std::uint32_t i : particles) {
      for (std::uint32_t j : particles) {
        if (i != j) neighbours[i].push_back(j);
      }
    }
  }
  row_offset_.assign(n + 1, 0);
  for (std::size_t p = 0; p < n; ++p) {
    std::sort(neighbours[p].begin(), neighbours[p].end());
    neighbours[p].erase(std::unique(neighbours[p].begin(), neighbours[p].end()), neighbours[p].end());
    row_offset_[p + 1] = row_offset_[p] + static_cast<std::uint32_t>(neighbours[p].size());
  }
  column_.reserve(row_offset_.back());
  for (const auto& row : neighbours) column_.insert(column_.end(), row.begin(), row.end());
  block_.resize(column_.size());

  connector_block_.resize(2 * model.connector_count());
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    const auto& particles = model.connector_particles[e];
    for (std::size_t i = 0; i < 2; ++i) {
      for (std::size_t j = 0; j < 2; ++j) {
        connector_block_[2 * e + i][j] = find_block(row_offset_, column_, particles[i], particles[j]);
      }
    }
  }
  radial_block_.resize(3 * model.radial_count());
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    const auto& particles = model.radial_particles[r];
    for (std::size_t i = 0; i < 3; ++i) {
      for (std::size_t j = 0; j < 3; ++j) {
        radial_block_[3 * r + i][j] = find_block(row_offset_, column_, particles[i], particles[j]);
      }
    }
  }

  preconditioner_.resize(n);
  free_.resize(n);
  for (std::size_t p = 0; p < n; ++p) free_[p] = model.is_anchored(p) ? 0 : 1;
  for (std::vector<Vec3>* vector :
       {&displacement_, &rhs_, &dv_, &residual_, &preconditioned_, &direction_, &product_}) {
    vector->assign(n, Vec3{});
  }
  block_sum_a_.resize(block_count(n));
  block_sum_b_.resize(block_count(n));
  block_sum_c_.resize(block_count(n));
}

ImplicitEuler::Powers ImplicitEuler::evaluate(double time, std::span<const Vec3> position,
                                              std::span<const Vec3> velocity) {
  ScopedTimer timer(force_seconds_);
  ++stats_.force_evaluations;
  const ForcePowers powers = evaluate_forces(model_, position, velocity, options_.terms, threads_, buffers_, force_);
  Powers out{powers.damping, powers.drag, 0.0};
  // The power of the force each anchor exerts to keep its particle on the path, m a - f (as in
  // ClothDynamics::evaluate).
  for (const Anchor& anchor : model_.anchors) {
    const std::uint32_t p = anchor.particle;
    out.anchor += dot(velocity[p], model_.particle_mass[p] * anchor.path.acceleration(time) - force_[p]);
  }
  std::copy(position.begin(), position.end(), evaluated_position_.begin());
  std::copy(velocity.begin(), velocity.end(), evaluated_velocity_.begin());
  evaluated_time_ = time;
  evaluated_valid_ = true;
  return out;
}

void ImplicitEuler::compute_element_jacobians(const ClothState& state) {
  const ForceTerms terms = options_.terms;
  const bool connectors = (terms & kConnectorSprings) != 0;
  const bool damped = (terms & kSpringDamping) != 0;
  const std::span<const Vec3> x = state.position;
  const std::span<const Vec3> v = state.velocity;
  parallel_for(model_.connector_count(), threads_, [&](std::size_t e) {
    if (!connectors) {
      connector_jacobian_[e] = {};
      return;
    }
    const auto [a, b] = model_.connector_particles[e];
    connector_jacobian_[e] =
        element::connector_jacobian(x[a], x[b], model_.connector_rest_length[e], model_.connector_stiffness[e],
                                    damped ? model_.connector_damping[e] : 0.0, /*clamp_compression=*/true);
  });
  parallel_for(model_.radial_count(), threads_, [&](std::size_t r) {
    const ForceTerms term =
        model_.radial_kind[r] == RadialKind::adjacent ? kAdjacentRadialSprings : kOppositeRadialSprings;
    if ((terms & term) == 0) {
      radial_jacobian_[r] = {};
      return;
    }
    const auto [centre, b, c] = model_.radial_particles[r];
    radial_jacobian_[r] =
        element::radial_jacobian(x[centre], x[b], x[c], v[centre], v[b], v[c], model_.radial_rest_angle[r],
                                 model_.radial_stiffness[r], damped ? model_.radial_damping[r] : 0.0);
  });
}

void ImplicitEuler::assemble(double h) {
  const double h2 = h * h;
  const double drag = (options_.terms & kAirDrag) != 0 ? model_.environment.air_drag : 0.0;
  const std::size_t radial_base = model_.radial_slot_base();
  parallel_for(model_.particle_count(), threads_, [&](std::size_t p) {
    const std::uint32_t begin = row_offset_[p];
    const std::uint32_t end = row_offset_[p + 1];
    for (std::uint32_t k = begin; k < end; ++k) block_[k] = Mat3{};
    if (!free_[p]) {
      // Anchored rows are not part of the system; their dv is known.
      preconditioner_[p] = Mat3{};
      rhs_[p] = Vec3{};
      return;
    }
    // K z: the stiffness times the position change the linearisation assumes, h v0 for free
    // particles and the path's displacement for anchored ones.
    Vec3 stiffness_times_displacement;
    std::uint32_t diagonal = 0;
    for (std::uint32_t k = model_.gather_offset[p]; k < model_.gather_offset[p + 1]; ++k) {
      const std::uint32_t slot = model_.gather_slot[k];
      if (slot < radial_base) {
        const std::uint32_t e = slot / 2;
        const std::uint32_t i = slot % 2;
        const element::ConnectorJacobian& jacobian = connector_jacobian_[e];
        const Mat3 a = h2 * jacobian.stiffness + h * jacobian.damping;
        const std::uint32_t other = model_.connector_particles[e][1 - i];
        diagonal = connector_block_[slot][i];
        block_[diagonal] += a;
        block_[connector_block_[slot][1 - i]] -= a;
        stiffness_times_displacement += jacobian.stiffness * (displacement_[p] - displacement_[other]);
      } else {
        const std::size_t local = slot - radial_base;
        const std::size_t r = local / 3;
        const int i = static_cast<int>(local % 3);
        const element::RadialJacobian& jacobian = radial_jacobian_[r];
        const auto& particles = model_.radial_particles[r];
        for (int j = 0; j < 3; ++j) {
          const Mat3 stiffness = jacobian.stiffness_block(i, j);
          block_[radial_block_[local][static_cast<std::size_t>(j)]] +=
              h2 * stiffness + h * jacobian.damping_block(i, j);
          stiffness_times_displacement += stiffness * displacement_[particles[static_cast<std::size_t>(j)]];
        }
        diagonal = radial_block_[local][static_cast<std::size_t>(i)];
      }
    }
    if (model_.gather_offset[p] == model_.gather_offset[p + 1]) {
      diagonal = static_cast<std::uint32_t>(
          std::lower_bound(column_.begin() + begin, column_.begin() + end, static_cast<std::uint32_t>(p)) -
          column_.begin());
    }
    block_[diagonal] += Mat3::diagonal(model_.particle_mass[p] + h * drag);
    rhs_[p] = h * (force_[p] - stiffness_times_displacement);
    preconditioner_[p] = inverse(block_[diagonal]);
  });
}

int ImplicitEuler::solve() {
  const std::size_t n = model_.particle_count();
  const auto row_product = [&](std::size_t p, const std::vector<Vec3>& vector) {
    Vec3 sum;
    for (std::uint32_t k = row_offset_[p]; k < row_offset_[p + 1]; ++k) sum += block_[k] * vector[column_[k]];
    return sum;
  };

  // r = b - A dv (anchored columns included), z = P r, p = z.
  const std::array<double, 3> initial =
      blocked_sums(n, threads_, block_sum_a_, block_sum_b_, block_sum_c_, [&](std::size_t begin, std::size_t end) {
        std::array<double, 3> sums{};
        for (std::size_t p = begin; p < end; ++p) {
          if (!free_[p]) {
            residual_[p] = preconditioned_[p] = direction_[p] = Vec3{};
            continue;
          }
          const Vec3 r = rhs_[p] - row_product(p, dv_);
          const Vec3 z = preconditioner_[p] * r;
          residual_[p] = r;
          preconditioned_[p] = z;
          direction_[p] = z;
          sums[0] += dot(r, z);
          sums[1] += squared_norm(r);
          sums[2] += squared_norm(rhs_[p]);
        }
        return sums;
      });
  double rho = initial[0];
  double residual_norm2 = initial[1];
  const double target = settings_.cg_tolerance * settings_.cg_tolerance * initial[2];
  if (residual_norm2 <= target) return 0;

  for (int iteration = 1; iteration <= settings_.cg_max_iterations; ++iteration) {
    // q = A p, and p . q.
    const double curvature =
        blocked_sums(n, threads_, block_sum_a_, block_sum_b_, block_sum_c_, [&](std::size_t begin, std::size_t end) {
          std::array<double, 3> sums{};
          for (std::size_t p = begin; p < end; ++p) {
            if (!free_[p]) {
              product_[p] = Vec3{};
              continue;
            }
            product_[p] = row_product(p, direction_);
            sums[0] += dot(direction_[p], product_[p]);
          }
          return sums;
        })[0];
    if (!(curvature > 0.0)) return iteration;  // breakdown: A p = 0 or non-finite; keep the iterate
    const double alpha = rho / curvature;
    // dv += alpha p, r -= alpha q, z = P r; r . z and |r|^2.
    const std::array<double, 3> updated =
        blocked_sums(n, threads_, block_sum_a_, block_sum_b_, block_sum_c_, [&](std::size_t begin, std::size_t end) {
          std::array<double, 3> sums{};
          for (std::size_t p = begin; p < end; ++p) {
            if (!free_[p]) continue;
            dv_[p] += alpha * direction_[p];
            const Vec3 r = residual_[p] - alpha * product_[p];
            const Vec3 z = preconditioner_[p] * r;
            residual_[p] = r;
            preconditioned_[p] = z;
            sums[0] += dot(r, z);
            sums[1] += squared_norm(r);
          }
          return sums;
        });
    residual_norm2 = updated[1];
    if (residual_norm2 <= target || !std::isfinite(residual_norm2)) return iteration;
    const double beta = updated[0] / rho;
    rho = updated[0];
    parallel_for(n, threads_, [&](std::size_t p) {
      if (free_[p]) direction_[p] = preconditioned_[p] + beta * direction_[p];
    });
  }
  ++stats_.unconverged_solves;
  return settings_.cg_max_iterations;
}

StepOutcome ImplicitEuler::step(ClothState& state, double t_limit) {
  CLOTHSIM_ASSERT(t_limit > state.time, "step() needs a limit after the current time");
  const std::size_t n = model_.particle_count();
  bool clipped = false;
  const double h = clip_step(state.time, settings_.time_step, t_limit, clipped);
  const double end_time = clipped ? t_limit : state.time + h;

  // f0: reuse the forces of the previous step's end when the state is still that one.
  const bool reusable = evaluated_valid_ && evaluated_time_ == state.time &&
                        std::equal(state.position.begin(), state.position.end(), evaluated_position_.begin()) &&
                        std::equal(state.velocity.begin(), state.velocity.end(), evaluated_velocity_.begin());
  if (!reusable) evaluate(state.time, state.position, state.velocity);

  compute_element_jacobians(state);
  parallel_for(n, threads_, [&](std::size_t p) {
    if (free_[p]) displacement_[p] = h * state.velocity[p];
  });
  for (const Anchor& anchor : model_.anchors) {
    const std::uint32_t p = anchor.particle;
    displacement_[p] = anchor.path.position(end_time) - state.position[p];
    dv_[p] = anchor.path.velocity_at(end_time) - state.velocity[p];
  }
  assemble(h);
  last_iterations_ = solve();
  stats_.linear_iterations += static_cast<std::uint64_t>(last_iterations_);
  stats_.max_linear_iterations = std::max(stats_.max_linear_iterations, static_cast<std::uint64_t>(last_iterations_));

  for (std::size_t p = 0; p < n; ++p) {
    if (free_[p] && !is_finite(dv_[p])) {
      // Leave the state as it was: the caller keeps the last good state.
      std::fill(dv_.begin(), dv_.end(), Vec3{});
      return {StepStatus::non_finite, h, static_cast<std::uint32_t>(p), true};
    }
  }
  parallel_for(n, threads_, [&](std::size_t p) {
    if (!free_[p]) return;
    state.velocity[p] += dv_[p];
    state.position[p] += h * state.velocity[p];
  });
  for (const Anchor& anchor : model_.anchors) {
    state.position[anchor.particle] = anchor.path.position(end_time);
    state.velocity[anchor.particle] = anchor.path.velocity_at(end_time);
  }
  state.time = end_time;

  // Work integrals with the end-of-step powers (backward Euler quadrature).
  const Powers powers = evaluate(state.time, state.position, state.velocity);
  state.damping_work += h * powers.damping;
  state.drag_work += h * powers.drag;
  state.anchor_work += h * powers.anchor;

  ++stats_.accepted_steps;
  stats_.smallest_step = std::min(stats_.smallest_step, h);
  stats_.largest_step = std::max(stats_.largest_step, h);
  stats_.last_step = h;
  return {StepStatus::ok, h, 0, false};
}

}  // namespace clothsim
