#include "integrators/implicit_euler.h"

#include <algorithm>
#include <cmath>

#include "core/assert.h"
#include "core/parallel.h"
#include "core/step_profile.h"
#include "integrators/dynamics.h"

namespace clothsim {
namespace {

// Particles per block of the deterministic reductions; fixed, never derived from the thread count.
constexpr std::size_t kReductionBlock = 1024;

// Side of the square aggregates of the coarse-grid correction, particles.
constexpr std::size_t kAggregateSize = 4;

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
  CLOTHSIM_ASSERT(options.precision == Precision::float64,
                  "implicit Euler's forces are float64 (sim/backend.h refuses float32 with it)");
  const std::size_t n = model.particle_count();
  buffers_.resize(model);
  gather_.build(model);
  force_.resize(n);
  evaluated_position_.resize(n);
  evaluated_velocity_.resize(n);
  connector_jacobian_.resize(model.connector_count());
  radial_jacobian_.resize(model.radial_count());

  // Block structure: each particle's neighbours through any element, and itself, ascending, found
  // through its elements in the gather table one particle at a time (a list per particle, or one
  // flat list of every element's pairs, would briefly need more memory than the matrix's
  // pattern itself: 2 to 4 times the 52 bytes per particle of column_).
  std::vector<std::uint32_t> pattern_row;
  const auto neighbours = [&](std::size_t p) -> const std::vector<std::uint32_t>& {
    std::vector<std::uint32_t>& row = pattern_row;
    row.assign(1, static_cast<std::uint32_t>(p));
    for (std::uint32_t k = gather_.offset[p]; k < gather_.offset[p + 1]; ++k) {
      const std::size_t slot = gather_.slot[k];
      if (slot < model.radial_slot_base()) {
        for (std::uint32_t q : model.connector_particles[slot / 2]) row.push_back(q);
      } else {
        for (std::uint32_t q : model.radial_particles[(slot - model.radial_slot_base()) / 3]) row.push_back(q);
      }
    }
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    return row;
  };
  row_offset_.assign(n + 1, 0);
  for (std::size_t p = 0; p < n; ++p) {
    row_offset_[p + 1] = row_offset_[p] + static_cast<std::uint32_t>(neighbours(p).size());
  }
  column_.reserve(row_offset_.back());
  for (std::size_t p = 0; p < n; ++p) {
    const std::vector<std::uint32_t>& columns = neighbours(p);
    column_.insert(column_.end(), columns.begin(), columns.end());
  }
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
  revision_ = model.revision;
  for (std::vector<Vec3>* vector :
       {&displacement_, &rhs_, &dv_, &residual_, &preconditioned_, &direction_, &product_, &held_normal_}) {
    vector->assign(n, Vec3{});
  }
  hold_.assign(n, Hold::none);
  slipped_.assign(n, 0);
  const bool lattice = model.rows > 0 && model.cols > 0 &&
                       static_cast<std::size_t>(model.rows) * static_cast<std::size_t>(model.cols) == n;
  if (settings.cg_two_level && settings.cg_multigrid && lattice) {
    multigrid_.emplace(static_cast<std::size_t>(model.rows), static_cast<std::size_t>(model.cols));
  } else if (settings.cg_two_level && lattice) {
    // Aggregates of kAggregateSize x kAggregateSize particles, numbered row by row.
    const std::size_t aggregate_cols = (static_cast<std::size_t>(model.cols) + kAggregateSize - 1) / kAggregateSize;
    const std::size_t aggregate_rows = (static_cast<std::size_t>(model.rows) + kAggregateSize - 1) / kAggregateSize;
    particle_aggregate_.resize(n);
    for (std::size_t p = 0; p < n; ++p) {
      const std::size_t row = p / static_cast<std::size_t>(model.cols);
      const std::size_t col = p % static_cast<std::size_t>(model.cols);
      particle_aggregate_[p] =
          static_cast<std::uint32_t>((row / kAggregateSize) * aggregate_cols + col / kAggregateSize);
    }
    // The coarse matrix's bandwidth from the blocks themselves. Elements reach two particles
    // away, so aggregates couple to their 8 neighbours only: at most aggregate_cols + 1 apart.
    std::size_t farthest = 0;
    for (std::size_t p = 0; p < n; ++p) {
      for (std::uint32_t k = row_offset_[p]; k < row_offset_[p + 1]; ++k) {
        const std::uint32_t a = particle_aggregate_[p];
        const std::uint32_t b = particle_aggregate_[column_[k]];
        farthest = std::max<std::size_t>(farthest, a > b ? a - b : b - a);
      }
    }
    coarse_factor_.resize(3 * aggregate_rows * aggregate_cols, 3 * farthest + 2);
    coarse_vector_.resize(coarse_factor_.dofs());
  }
  block_sum_a_.resize(block_count(n));
  block_sum_b_.resize(block_count(n));
  block_sum_c_.resize(block_count(n));
}

std::size_t ImplicitEuler::workspace_bytes() const {
  const auto bytes = [](const auto& vector) { return vector.capacity() * sizeof(vector[0]); };
  std::size_t total = buffers_.bytes() + gather_.bytes();
  total += bytes(force_) + bytes(evaluated_position_) + bytes(evaluated_velocity_);
  total += bytes(connector_jacobian_) + bytes(radial_jacobian_);
  total += bytes(row_offset_) + bytes(column_) + bytes(block_) + bytes(connector_block_) + bytes(radial_block_);
  total += bytes(preconditioner_) + bytes(free_);
  total += bytes(displacement_) + bytes(rhs_) + bytes(dv_) + bytes(residual_) + bytes(preconditioned_) +
           bytes(direction_) + bytes(product_);
  total += bytes(particle_aggregate_) + coarse_factor_.bytes() + bytes(coarse_vector_);
  if (multigrid_) total += multigrid_->bytes();
  total += bytes(block_sum_a_) + bytes(block_sum_b_) + bytes(block_sum_c_);
  total += bytes(hold_) + bytes(slipped_) + bytes(held_normal_);
  return total;
}

std::size_t ImplicitEuler::workspace_bytes_for(const LatticeCounts& counts, const IntegratorSettings& settings) {
  const std::size_t n = counts.particles;
  const std::size_t rows = counts.rows;
  const std::size_t cols = counts.cols;
  // Blocks: particle pairs joined by an element, itself included: offsets (0, 0), (0, +-1),
  // (+-1, 0), the 4 diagonals (adjacent radial springs) and (0, +-2), (+-2, 0) (opposite ones).
  const auto pairs = [&](std::size_t row_offset, std::size_t col_offset) -> std::size_t {
    return rows > row_offset && cols > col_offset ? (rows - row_offset) * (cols - col_offset) : 0;
  };
  const std::size_t blocks =
      pairs(0, 0) + 2 * (pairs(0, 1) + pairs(1, 0) + 2 * pairs(1, 1) + pairs(0, 2) + pairs(2, 0));
  std::size_t total = GatherTable::bytes_for(counts);
  total += 3 * n * sizeof(Vec3);  // forces and the state they were evaluated at
  total += counts.connectors * sizeof(element::ConnectorJacobian) + counts.radials * sizeof(element::RadialJacobian);
  total += (n + 1 + blocks) * sizeof(std::uint32_t) + blocks * sizeof(Mat3);
  total += 2 * counts.connectors * sizeof(std::array<std::uint32_t, 2>) +
           3 * counts.radials * sizeof(std::array<std::uint32_t, 3>);
  total += n * (sizeof(Mat3) + sizeof(std::uint8_t));  // preconditioner, free
  total += 8 * n * sizeof(Vec3);                       // 7 CG vectors and the held normals
  total += n * (sizeof(Hold) + sizeof(std::uint8_t));  // hold, slipped
  total += 3 * block_count(n) * sizeof(double);
  if (settings.cg_two_level && settings.cg_multigrid && n > 0) {
    total += LatticeMultigrid::bytes_for(rows, cols);
  } else if (settings.cg_two_level && n > 0) {
    const std::size_t aggregate_cols = (cols + kAggregateSize - 1) / kAggregateSize;
    const std::size_t aggregate_rows = (rows + kAggregateSize - 1) / kAggregateSize;
    const std::size_t dofs = 3 * aggregate_rows * aggregate_cols;
    // Aggregates couple to their 8 neighbours: at most aggregate_cols + 1 apart (the constructor
    // measures it; this is its value from 5 x 5 particles on).
    const std::size_t bandwidth = 3 * (aggregate_cols + 1) + 2;
    total += n * sizeof(std::uint32_t) + BandedCholesky::bytes_for(dofs, bandwidth) + dofs * sizeof(double);
  }
  return total;
}

ImplicitEuler::Powers ImplicitEuler::evaluate(double time, std::span<const Vec3> position,
                                              std::span<const Vec3> velocity) {
  StageTimer timer(profile_, StepStage::forces);
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
    if (!connectors || model_.connector_live[e] == 0) {
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
    if ((terms & term) == 0 || model_.radial_live[r] == 0) {
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
    for (std::uint32_t k = gather_.offset[p]; k < gather_.offset[p + 1]; ++k) {
      const std::uint32_t slot = gather_.slot[k];
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
    if (gather_.offset[p] == gather_.offset[p + 1]) {
      diagonal = static_cast<std::uint32_t>(
          std::lower_bound(column_.begin() + begin, column_.begin() + end, static_cast<std::uint32_t>(p)) -
          column_.begin());
    }
    block_[diagonal] += Mat3::diagonal(model_.particle_mass[p] + h * drag);
    rhs_[p] = h * (force_[p] - stiffness_times_displacement);
    preconditioner_[p] = inverse(block_[diagonal]);
  });
}

double ImplicitEuler::precondition() {
  const std::size_t n = model_.particle_count();
  if (multigrid_) {
    multigrid_->apply(residual_, preconditioned_, threads_);
    return blocked_sums(n, threads_, block_sum_a_, block_sum_b_, block_sum_c_, [&](std::size_t begin, std::size_t end) {
      std::array<double, 3> sums{};
      for (std::size_t p = begin; p < end; ++p) sums[0] += dot(residual_[p], preconditioned_[p]);
      return sums;
    })[0];
  }
  const bool coarse = coarse_factor_.dofs() > 0;
  if (coarse) {
    // Restriction (sums over each aggregate's free particles, in particle order), then the
    // coarse solve by the banded Cholesky factor.
    std::fill(coarse_vector_.begin(), coarse_vector_.end(), 0.0);
    for (std::size_t p = 0; p < n; ++p) {
      if (!free_[p]) continue;
      double* target = &coarse_vector_[3 * particle_aggregate_[p]];
      target[0] += residual_[p].x;
      target[1] += residual_[p].y;
      target[2] += residual_[p].z;
    }
    coarse_factor_.solve(coarse_vector_);
  }
  return blocked_sums(n, threads_, block_sum_a_, block_sum_b_, block_sum_c_, [&](std::size_t begin, std::size_t end) {
    std::array<double, 3> sums{};
    for (std::size_t p = begin; p < end; ++p) {
      if (!free_[p]) {
        preconditioned_[p] = Vec3{};
        continue;
      }
      Vec3 z = preconditioner_[p] * residual_[p];
      if (coarse) {
        const double* correction = &coarse_vector_[3 * particle_aggregate_[p]];
        z += Vec3{correction[0], correction[1], correction[2]};
      }
      z = held(p, z);
      preconditioned_[p] = z;
      sums[0] += dot(residual_[p], z);
    }
    return sums;
  })[0];
}

std::uint32_t ImplicitEuler::diagonal_block(std::size_t p) const {
  return find_block(row_offset_, column_, static_cast<std::uint32_t>(p), static_cast<std::uint32_t>(p));
}

Vec3 ImplicitEuler::row_product(std::size_t p, const std::vector<Vec3>& vector) const {
  Vec3 sum;
  for (std::uint32_t k = row_offset_[p]; k < row_offset_[p + 1]; ++k) sum += block_[k] * vector[column_[k]];
  return sum;
}

int ImplicitEuler::solve() {
  const std::size_t n = model_.particle_count();

  // r = b - A dv (anchored columns included).
  const std::array<double, 3> initial =
      blocked_sums(n, threads_, block_sum_a_, block_sum_b_, block_sum_c_, [&](std::size_t begin, std::size_t end) {
        std::array<double, 3> sums{};
        for (std::size_t p = begin; p < end; ++p) {
          if (!free_[p]) {
            residual_[p] = direction_[p] = Vec3{};
            continue;
          }
          const Vec3 r = held(p, rhs_[p] - row_product(p, dv_));
          residual_[p] = r;
          sums[1] += squared_norm(r);
          // The target is relative to the whole right-hand side, held directions included: at
          // rest on a floor the filtered one is nearly zero, and a target relative to it would ask
          // for a far smaller residual than the loads the step resolves.
          sums[2] += squared_norm(rhs_[p]);
        }
        return sums;
      });
  const double target = settings_.cg_tolerance * settings_.cg_tolerance * initial[2];
  if (initial[1] <= target) return 0;
  // z = M^-1 r, p = z.
  double rho = precondition();
  parallel_for(n, threads_, [&](std::size_t p) { direction_[p] = preconditioned_[p]; });

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
            product_[p] = held(p, row_product(p, direction_));
            sums[0] += dot(direction_[p], product_[p]);
          }
          return sums;
        })[0];
    if (!(curvature > 0.0)) return iteration;  // breakdown: A p = 0 or non-finite; keep the iterate
    const double alpha = rho / curvature;
    // dv += alpha p, r -= alpha q; |r|^2.
    const double residual_norm2 =
        blocked_sums(n, threads_, block_sum_a_, block_sum_b_, block_sum_c_, [&](std::size_t begin, std::size_t end) {
          std::array<double, 3> sums{};
          for (std::size_t p = begin; p < end; ++p) {
            if (!free_[p]) continue;
            dv_[p] += alpha * direction_[p];
            residual_[p] -= alpha * product_[p];
            sums[0] += squared_norm(residual_[p]);
          }
          return sums;
        })[0];
    if (residual_norm2 <= target || !std::isfinite(residual_norm2)) return iteration;
    const double rho_next = precondition();
    const double beta = rho_next / rho;
    rho = rho_next;
    parallel_for(n, threads_, [&](std::size_t p) {
      if (free_[p]) direction_[p] = preconditioned_[p] + beta * direction_[p];
    });
  }
  ++stats_.cg_unconverged_solves;
  return settings_.cg_max_iterations;
}

void ImplicitEuler::assemble_coarse() {
  if (multigrid_) {
    multigrid_->setup({row_offset_, column_, block_, preconditioner_, free_, hold_, held_normal_, holding_}, threads_);
    return;
  }
  if (coarse_factor_.dofs() == 0) return;
  const std::size_t n = model_.particle_count();
  coarse_factor_.clear();
  // The lower triangle of P^T A P over the free particles; P sums each aggregate's particles.
  for (std::size_t p = 0; p < n; ++p) {
    if (!free_[p]) continue;
    const std::size_t row_aggregate = particle_aggregate_[p];
    for (std::uint32_t k = row_offset_[p]; k < row_offset_[p + 1]; ++k) {
      const std::uint32_t q = column_[k];
      if (!free_[q]) continue;
      const std::size_t column_aggregate = particle_aggregate_[q];
      if (column_aggregate > row_aggregate) continue;
      const Mat3 block =
          holding_ ? held_block(block_[k], hold_[p], held_normal_[p], hold_[q], held_normal_[q]) : block_[k];
      for (int r = 0; r < 3; ++r) {
        const std::size_t i = 3 * row_aggregate + static_cast<std::size_t>(r);
        for (int c = 0; c < 3; ++c) {
          const std::size_t j = 3 * column_aggregate + static_cast<std::size_t>(c);
          if (j <= i) coarse_factor_.lower(i, j) += block(r, c);
        }
      }
    }
  }
  // Aggregates without free particles get an identity block (BandedCholesky::factor): their
  // right-hand side is always zero.
  coarse_factor_.factor();
}

StepOutcome ImplicitEuler::step(ClothState& state, double t_limit) {
  CLOTHSIM_ASSERT(t_limit > state.time, "step() needs a limit after the current time");
  const std::size_t n = model_.particle_count();
  bool clipped = false;
  const double h = clip_step(state.time, settings_.time_step, t_limit, clipped);
  const double end_time = clipped ? t_limit : state.time + h;

  // A model edit between steps (an anchor released, a spring broken or yielded) changes which
  // particles are integrated and the forces of the previous step's end.
  if (model_.revision != revision_) {
    for (std::size_t p = 0; p < n; ++p) free_[p] = model_.is_anchored(p) ? 0 : 1;
    evaluated_valid_ = false;
    revision_ = model_.revision;
  }
  // f0: reuse the forces of the previous step's end when the state and the model are still those.
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
  hold_on_surfaces(state, h);
  assemble_coarse();
  last_iterations_ = solve();
  if (release_held_particles()) {
    // The multigrid's levels are built for the held set; the aggregates' coarse matrix keeps the
    // first one (the additive correction stays definite with any).
    if (multigrid_) assemble_coarse();
    last_iterations_ += solve();
  }
  stats_.cg_iterations += static_cast<std::uint64_t>(last_iterations_);
  stats_.cg_max_iterations_in_a_step =
      std::max(stats_.cg_max_iterations_in_a_step, static_cast<std::uint64_t>(last_iterations_));

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
  book_surface_impulses(state);

  // Work integrals with the end-of-step powers (backward Euler quadrature).
  const Powers powers = evaluate(state.time, state.position, state.velocity);
  state.damping_work += h * powers.damping;
  state.drag_work += h * powers.drag;
  state.anchor_work += h * powers.anchor;

  record_accepted_step(h);
  return {StepStatus::ok, h, 0, false};
}

void ImplicitEuler::transfer_state(StateArchive& archive) {
  Integrator::transfer_state(archive);
  archive.array("implicit_euler.dv", dv_);
  archive.array("implicit_euler.slipped", slipped_);
  // The forces of the last step's end, which the next step reuses (advance): restored with what
  // they were computed at, so that a resumed run evaluates exactly what the uninterrupted one does
  // (summary.json's force_evaluations included).
  archive.array("implicit_euler.evaluated_force", force_);
  archive.array("implicit_euler.evaluated_position", evaluated_position_);
  archive.array("implicit_euler.evaluated_velocity", evaluated_velocity_);
  archive.value("implicit_euler.evaluated_time", evaluated_time_);
  archive.value("implicit_euler.evaluated_valid", evaluated_valid_);
  archive.value("implicit_euler.model_revision", revision_);
  // Which particles are integrated follows the restored model (the next model change moves them again).
  if (archive.loading()) {
    for (std::size_t p = 0; p < free_.size(); ++p) free_[p] = model_.is_anchored(p) ? 0 : 1;
  }
}

}  // namespace clothsim
