#include "integrators/block_system.h"

#include <algorithm>
#include <cmath>

#include "core/assert.h"
#include "core/multiversion.h"
#include "core/parallel.h"

namespace clothsim {
namespace {

// Particles per block of the deterministic reductions; fixed, never derived from the thread count.
constexpr std::size_t kReductionBlock = 1024;

// How far ahead of the row it assembles the assembly prefetches a row's element Jacobians,
// particles, and the cache line it prefetches by, bytes. A row reads the Jacobians of the radial
// springs centred a lattice row further on for the first time, in no order that the hardware's
// prefetchers follow; on 128 x 128 cotton this took the assembly from 7.8 to 7.0 ms a step
// (docs/performance.md, "The implicit step's parts in the profile, and a cheaper assembly"). The
// same bits either way.
constexpr std::size_t kPrefetchAhead = 8;
constexpr std::size_t kCacheLine = 64;

// Side of the square aggregates of the coarse-grid correction, particles.
constexpr std::size_t kAggregateSize = 4;

std::size_t block_count(std::size_t n) { return (n + kReductionBlock - 1) / kReductionBlock; }

std::uint32_t find_block(const std::vector<std::uint32_t>& row_offset, const std::vector<std::uint32_t>& column,
                         std::uint32_t row, std::uint32_t col) {
  const auto first = column.begin() + row_offset[row];
  const auto last = column.begin() + row_offset[row + 1];
  const auto it = std::lower_bound(first, last, col);
  CLOTHSIM_ASSERT(it != last && *it == col, "every element pair has a block");
  return static_cast<std::uint32_t>(it - column.begin());
}

}  // namespace

// Sums body(begin, end) -> std::array<double, 3> over fixed blocks of the particles, the blocks in
// parallel and their results added in block order: the same bits for any thread count.
template <typename Body>
std::array<double, 3> BlockSystem::blocked_sums(Body&& body) {
  const std::size_t n = model_.particle_count();
  const std::size_t blocks = block_count(n);
  parallel_for(blocks, threads_, [&](std::size_t b) {
    const std::size_t begin = b * kReductionBlock;
    const std::array<double, 3> sums = body(begin, std::min(n, begin + kReductionBlock));
    block_sum_a_[b] = sums[0];
    block_sum_b_[b] = sums[1];
    block_sum_c_[b] = sums[2];
  });
  std::array<double, 3> total{};
  for (std::size_t b = 0; b < blocks; ++b) {
    total[0] += block_sum_a_[b];
    total[1] += block_sum_b_[b];
    total[2] += block_sum_c_[b];
  }
  return total;
}

BlockSystem::BlockSystem(const ClothModel& model, const IntegratorSettings& settings, int threads, StepProfile& profile)
    : model_(model), threads_(threads), profile_(profile) {
  const std::size_t n = model.particle_count();
  gather_.build(model);
  connector_jacobian.resize(model.connector_count());
  radial_jacobian.resize(model.radial_count());

  // Block structure: each particle's neighbours through any element, and itself, ascending, found
  // through its elements in the gather table one particle at a time (a list per particle, or one
  // flat list of every element's pairs, would briefly need more memory than the matrix's
  // pattern itself: 2 to 4 times the 52 bytes per particle of column).
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
  row_offset.assign(n + 1, 0);
  for (std::size_t p = 0; p < n; ++p) {
    row_offset[p + 1] = row_offset[p] + static_cast<std::uint32_t>(neighbours(p).size());
  }
  column.reserve(row_offset.back());
  for (std::size_t p = 0; p < n; ++p) {
    const std::vector<std::uint32_t>& columns = neighbours(p);
    column.insert(column.end(), columns.begin(), columns.end());
  }
  block.resize(column.size());

  connector_block.resize(2 * model.connector_count());
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    const auto& particles = model.connector_particles[e];
    for (std::size_t i = 0; i < 2; ++i) {
      for (std::size_t j = 0; j < 2; ++j) {
        connector_block[2 * e + i][j] = find_block(row_offset, column, particles[i], particles[j]);
      }
    }
  }
  radial_block.resize(3 * model.radial_count());
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    const auto& particles = model.radial_particles[r];
    for (std::size_t i = 0; i < 3; ++i) {
      for (std::size_t j = 0; j < 3; ++j) {
        radial_block[3 * r + i][j] = find_block(row_offset, column, particles[i], particles[j]);
      }
    }
  }

  preconditioner.resize(n);
  update_free();
  for (std::vector<Vec3>* vector :
       {&rhs, &solution, &residual_, &preconditioned_, &direction_, &product_, &held_normal}) {
    vector->assign(n, Vec3{});
  }
  hold.assign(n, Hold::none);
  const bool lattice = model.rows > 0 && model.cols > 0 &&
                       static_cast<std::size_t>(model.rows) * static_cast<std::size_t>(model.cols) == n;
  if (settings.cg_two_level && settings.cg_multigrid && lattice) {
    vcycle_threshold_ = settings.cg_vcycle_threshold;
    multigrid_.emplace(static_cast<std::size_t>(model.rows), static_cast<std::size_t>(model.cols),
                       settings.cg_line_smoother);
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
      for (std::uint32_t k = row_offset[p]; k < row_offset[p + 1]; ++k) {
        const std::uint32_t a = particle_aggregate_[p];
        const std::uint32_t b = particle_aggregate_[column[k]];
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

void BlockSystem::update_free() {
  free.resize(model_.particle_count());
  for (std::size_t p = 0; p < free.size(); ++p) free[p] = model_.is_anchored(p) ? 0 : 1;
}

std::size_t BlockSystem::bytes() const {
  const auto bytes = [](const auto& vector) { return vector.capacity() * sizeof(vector[0]); };
  std::size_t total = gather_.bytes();
  total += bytes(connector_jacobian) + bytes(radial_jacobian);
  total += bytes(row_offset) + bytes(column) + bytes(block) + bytes(connector_block) + bytes(radial_block);
  total += bytes(preconditioner) + bytes(free);
  total +=
      bytes(rhs) + bytes(solution) + bytes(residual_) + bytes(preconditioned_) + bytes(direction_) + bytes(product_);
  total += bytes(particle_aggregate_) + coarse_factor_.bytes() + bytes(coarse_vector_);
  if (multigrid_) total += multigrid_->bytes();
  total += bytes(block_sum_a_) + bytes(block_sum_b_) + bytes(block_sum_c_);
  total += bytes(hold) + bytes(held_normal);
  return total;
}

std::size_t BlockSystem::bytes_for(const LatticeCounts& counts, const IntegratorSettings& settings) {
  const std::size_t n = counts.particles;
  const std::size_t rows = counts.rows;
  const std::size_t cols = counts.cols;
  // Blocks: particle pairs joined by an element, itself included: offsets (0, 0), (0, +-1),
  // (+-1, 0), the 4 diagonals (adjacent radial springs) and (0, +-2), (+-2, 0) (opposite ones).
  const auto pairs = [&](std::size_t row_offset_count, std::size_t col_offset_count) -> std::size_t {
    return rows > row_offset_count && cols > col_offset_count ? (rows - row_offset_count) * (cols - col_offset_count)
                                                              : 0;
  };
  const std::size_t blocks =
      pairs(0, 0) + 2 * (pairs(0, 1) + pairs(1, 0) + 2 * pairs(1, 1) + pairs(0, 2) + pairs(2, 0));
  std::size_t total = GatherTable::bytes_for(counts);
  total += counts.connectors * sizeof(element::ConnectorJacobian) + counts.radials * sizeof(element::RadialJacobian);
  total += (n + 1 + blocks) * sizeof(std::uint32_t) + blocks * sizeof(Mat3);
  total += 2 * counts.connectors * sizeof(std::array<std::uint32_t, 2>) +
           3 * counts.radials * sizeof(std::array<std::uint32_t, 3>);
  total += n * (sizeof(Mat3) + sizeof(std::uint8_t));  // preconditioner, free
  total += 7 * n * sizeof(Vec3);                       // 6 CG vectors and the held normals
  total += n * sizeof(Hold);
  total += 3 * block_count(n) * sizeof(double);
  if (settings.cg_two_level && settings.cg_multigrid && n > 0) {
    total += LatticeMultigrid::bytes_for(rows, cols, settings.cg_line_smoother);
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

void BlockSystem::compute_jacobians(ForceTerms terms, std::span<const Vec3> x, std::span<const Vec3> v) {
  StageTimer timer(profile_, StepStage::jacobians);
  const ClothModel& model = model_;
  const bool connectors = (terms & kConnectorSprings) != 0;
  const bool damped = (terms & kSpringDamping) != 0;
  parallel_for(model.connector_count(), threads_, [&](std::size_t e) {
    if (!connectors || model.connector_live[e] == 0) {
      connector_jacobian[e] = {};
      return;
    }
    const auto [a, b] = model.connector_particles[e];
    connector_jacobian[e] =
        element::connector_jacobian(x[a], x[b], model.connector_rest_length[e], model.connector_stiffness[e],
                                    damped ? model.connector_damping[e] : 0.0, /*clamp_compression=*/true);
  });
  parallel_for(model.radial_count(), threads_, [&](std::size_t r) {
    const ForceTerms term =
        model.radial_kind[r] == RadialKind::adjacent ? kAdjacentRadialSprings : kOppositeRadialSprings;
    if ((terms & term) == 0 || model.radial_live[r] == 0) {
      radial_jacobian[r] = {};
      return;
    }
    const auto [centre, b, c] = model.radial_particles[r];
    const std::array<double, 2> fade = radial_fade_lengths(model, r);
    radial_jacobian[r] =
        element::radial_jacobian(x[centre], x[b], x[c], v[centre], v[b], v[c], model.radial_rest_angle[r],
                                 model.radial_stiffness[r], damped ? model.radial_damping[r] : 0.0, fade[0], fade[1]);
  });
}

void BlockSystem::prefetch_jacobians(std::size_t p) const {
  if (p >= model_.particle_count()) return;
  const std::size_t radial_base = model_.radial_slot_base();
  for (std::uint32_t k = gather_.offset[p]; k < gather_.offset[p + 1]; ++k) {
    const std::uint32_t slot = gather_.slot[k];
    const auto prefetch = [](const auto& jacobian) {
      const auto* first = reinterpret_cast<const char*>(&jacobian);
      for (std::size_t byte = 0; byte < sizeof(jacobian); byte += kCacheLine) __builtin_prefetch(first + byte);
    };
    if (slot < radial_base) {
      prefetch(connector_jacobian[slot / 2]);
    } else {
      prefetch(radial_jacobian[(slot - radial_base) / 3]);
    }
  }
}

void BlockSystem::assemble(ForceTerms terms, double damping_scale, double stiffness_scale,
                           std::span<const Vec3> displacement, std::span<Vec3> stiffness_product) {
  StageTimer timer(profile_, StepStage::assembly);
  const RowAssembly row{damping_scale, stiffness_scale, (terms & kAirDrag) != 0 ? model_.environment.air_drag : 0.0,
                        displacement, stiffness_product};
  parallel_for(model_.particle_count(), threads_, [&](std::size_t p) { assemble_row(p, row); });
}

// Compiled for each instruction set (core/multiversion.h): the assembly was a fifth of a step.
CLOTHSIM_MULTIVERSION void BlockSystem::assemble_row(std::size_t p, const RowAssembly& row) {
  const ClothModel& model = model_;
  const double damping_scale = row.damping_scale;
  const double stiffness_scale = row.stiffness_scale;
  const std::span<const Vec3> displacement = row.displacement;
  const bool product = !displacement.empty();
  const bool with_stiffness = stiffness_scale != 0.0 || product;
  const std::size_t radial_base = model.radial_slot_base();
  const std::uint32_t begin = row_offset[p];
  const std::uint32_t end = row_offset[p + 1];
  for (std::uint32_t k = begin; k < end; ++k) block[k] = Mat3{};
  if (!free[p]) {
    // Anchored rows are not part of the system; their unknown is known.
    preconditioner[p] = Mat3{};
    if (product) row.stiffness_product[p] = Vec3{};
    return;
  }
  prefetch_jacobians(p + kPrefetchAhead);
  Vec3 stiffness_times_displacement;
  std::uint32_t diagonal = 0;
  for (std::uint32_t k = gather_.offset[p]; k < gather_.offset[p + 1]; ++k) {
    const std::uint32_t slot = gather_.slot[k];
    if (slot < radial_base) {
      const std::uint32_t e = slot / 2;
      const std::uint32_t i = slot % 2;
      const element::ConnectorJacobian& jacobian = connector_jacobian[e];
      const Mat3 a = stiffness_scale * jacobian.stiffness + damping_scale * jacobian.damping;
      const std::uint32_t other = model.connector_particles[e][1 - i];
      diagonal = connector_block[slot][i];
      block[diagonal] += a;
      block[connector_block[slot][1 - i]] -= a;
      if (product) stiffness_times_displacement += jacobian.stiffness * (displacement[p] - displacement[other]);
    } else {
      const std::size_t local = slot - radial_base;
      const std::size_t r = local / 3;
      const int i = static_cast<int>(local % 3);
      const element::RadialJacobian& jacobian = radial_jacobian[r];
      const auto& particles = model.radial_particles[r];
      for (int j = 0; j < 3; ++j) {
        Mat3& target = block[radial_block[local][static_cast<std::size_t>(j)]];
        if (!with_stiffness) {
          // The IMEX stages' D alone: 0 K would add nothing but its cost.
          target += damping_scale * jacobian.damping_block(i, j);
          continue;
        }
        const Mat3 stiffness = jacobian.stiffness_block(i, j);
        target += stiffness_scale * stiffness + damping_scale * jacobian.damping_block(i, j);
        if (product) stiffness_times_displacement += stiffness * displacement[particles[static_cast<std::size_t>(j)]];
      }
      diagonal = radial_block[local][static_cast<std::size_t>(i)];
    }
  }
  if (gather_.offset[p] == gather_.offset[p + 1]) {
    diagonal = static_cast<std::uint32_t>(
        std::lower_bound(column.begin() + begin, column.begin() + end, static_cast<std::uint32_t>(p)) - column.begin());
  }
  block[diagonal] += Mat3::diagonal(model.particle_mass[p] + damping_scale * row.drag);
  if (product) row.stiffness_product[p] = stiffness_times_displacement;
  preconditioner[p] = inverse(block[diagonal]);
}

Vec3 BlockSystem::damping_product(std::size_t p, std::span<const Vec3> v, double drag) const {
  const std::size_t radial_base = model_.radial_slot_base();
  Vec3 sum = drag * v[p];
  for (std::uint32_t k = gather_.offset[p]; k < gather_.offset[p + 1]; ++k) {
    const std::uint32_t slot = gather_.slot[k];
    if (slot < radial_base) {
      const std::uint32_t e = slot / 2;
      const std::uint32_t other = model_.connector_particles[e][1 - slot % 2];
      sum += connector_jacobian[e].damping * (v[p] - v[other]);
    } else {
      // c g_i (g . v): the row of c g g^T without forming its blocks.
      const std::size_t local = slot - radial_base;
      const element::RadialJacobian& jacobian = radial_jacobian[local / 3];
      const auto& particles = model_.radial_particles[local / 3];
      double rate = 0.0;
      for (std::size_t j = 0; j < 3; ++j) rate += dot(jacobian.gradient[j], v[particles[j]]);
      sum += (jacobian.damping * rate) * jacobian.gradient[local % 3];
    }
  }
  return sum;
}

void BlockSystem::set_hold(std::size_t p, Hold how, const Vec3& normal) {
  hold[p] = how;
  held_normal[p] = how == Hold::none ? Vec3{} : normal;
  const Mat3& diagonal = block[diagonal_block(p)];
  switch (how) {
    case Hold::none: preconditioner[p] = inverse(diagonal); break;
    case Hold::normal: {
      // Block Jacobi on the two free directions: the inverse of S D S, completed by n n^T so that
      // it is invertible (the filter removes n again). With D symmetric,
      // S D S = D - n (D n)^T - (D n) n^T + (n . D n) n n^T.
      const Vec3 dn = diagonal * normal;
      preconditioner[p] =
          inverse(diagonal - outer(normal, dn) - outer(dn, normal) + (dot(normal, dn) + 1.0) * outer(normal, normal));
      break;
    }
    case Hold::all: preconditioner[p] = Mat3{}; break;
  }
}

double BlockSystem::precondition() {
  const std::size_t n = model_.particle_count();
  if (multigrid_ && vcycle_) {
    multigrid_->apply(residual_, preconditioned_, threads_);
    return blocked_sums([&](std::size_t begin, std::size_t end) {
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
      if (!free[p]) continue;
      double* target = &coarse_vector_[3 * particle_aggregate_[p]];
      target[0] += residual_[p].x;
      target[1] += residual_[p].y;
      target[2] += residual_[p].z;
    }
    coarse_factor_.solve(coarse_vector_);
  }
  return blocked_sums([&](std::size_t begin, std::size_t end) {
    std::array<double, 3> sums{};
    for (std::size_t p = begin; p < end; ++p) {
      if (!free[p]) {
        preconditioned_[p] = Vec3{};
        continue;
      }
      Vec3 z = preconditioner[p] * residual_[p];
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

std::uint32_t BlockSystem::diagonal_block(std::size_t p) const {
  return find_block(row_offset, column, static_cast<std::uint32_t>(p), static_cast<std::uint32_t>(p));
}

Vec3 BlockSystem::row_product(std::size_t p, std::span<const Vec3> vector) const {
  Vec3 sum;
  for (std::uint32_t k = row_offset[p]; k < row_offset[p + 1]; ++k) sum += block[k] * vector[column[k]];
  return sum;
}

BlockSystem::Solve BlockSystem::solve(double relative, double absolute, int max_iterations) {
  StageTimer timer(profile_, StepStage::linear_solve);
  const std::size_t n = model_.particle_count();

  // r = b - A u (anchored columns included).
  const std::array<double, 3> initial = blocked_sums([&](std::size_t begin, std::size_t end) {
    std::array<double, 3> sums{};
    for (std::size_t p = begin; p < end; ++p) {
      if (!free[p]) {
        residual_[p] = direction_[p] = Vec3{};
        continue;
      }
      const Vec3 r = held(p, rhs[p] - row_product(p, solution));
      residual_[p] = r;
      sums[1] += squared_norm(r);
      // The relative target is relative to the whole right-hand side, held directions included:
      // at rest on a floor the filtered one is nearly zero, and a target relative to it would ask
      // for a far smaller residual than the loads the step resolves.
      sums[2] += squared_norm(rhs[p]);
    }
    return sums;
  });
  const double target = std::max(relative * relative * initial[2], absolute * absolute);
  if (initial[1] <= target) return {0, true};
  // z = P^-1 r, p = z.
  double rho = precondition();
  parallel_for(n, threads_, [&](std::size_t p) { direction_[p] = preconditioned_[p]; });

  for (int iteration = 1; iteration <= max_iterations; ++iteration) {
    // q = A p, and p . q.
    const double curvature = blocked_sums([&](std::size_t begin, std::size_t end) {
      std::array<double, 3> sums{};
      for (std::size_t p = begin; p < end; ++p) {
        if (!free[p]) {
          product_[p] = Vec3{};
          continue;
        }
        product_[p] = held(p, row_product(p, direction_));
        sums[0] += dot(direction_[p], product_[p]);
      }
      return sums;
    })[0];
    if (!(curvature > 0.0)) return {iteration, true};  // breakdown: A p = 0 or non-finite; keep the iterate
    const double alpha = rho / curvature;
    // u += alpha p, r -= alpha q; |r|^2.
    const double residual_norm2 = blocked_sums([&](std::size_t begin, std::size_t end) {
      std::array<double, 3> sums{};
      for (std::size_t p = begin; p < end; ++p) {
        if (!free[p]) continue;
        solution[p] += alpha * direction_[p];
        residual_[p] -= alpha * product_[p];
        sums[0] += squared_norm(residual_[p]);
      }
      return sums;
    })[0];
    if (residual_norm2 <= target || !std::isfinite(residual_norm2)) return {iteration, true};
    const double rho_next = precondition();
    const double beta = rho_next / rho;
    rho = rho_next;
    parallel_for(n, threads_, [&](std::size_t p) {
      if (free[p]) direction_[p] = preconditioned_[p] + beta * direction_[p];
    });
  }
  return {max_iterations, false};
}

double BlockSystem::stiffness_ratio() {
  const std::size_t n = model_.particle_count();
  const std::size_t blocks = block_count(n);
  if (blocks == 0) return 0.0;
  parallel_for(blocks, threads_, [&](std::size_t b) {
    double largest = 0.0;
    for (std::size_t p = b * kReductionBlock; p < std::min(n, (b + 1) * kReductionBlock); ++p) {
      if (!free[p]) continue;
      const Mat3& diagonal = block[diagonal_block(p)];
      const double mass = model_.particle_mass[p];
      largest = std::max(largest, (diagonal(0, 0) + diagonal(1, 1) + diagonal(2, 2) - 3.0 * mass) / mass);
    }
    block_sum_a_[b] = largest;
  });
  return *std::max_element(block_sum_a_.begin(), block_sum_a_.begin() + static_cast<std::ptrdiff_t>(blocks));
}

double jacobi_iterations_estimate(double stiffness_ratio, int rows, int cols) {
  constexpr double kIterationsPerLatticeSide = 6.5;
  const double side = std::max(rows, cols);
  return std::min(std::sqrt(stiffness_ratio), kIterationsPerLatticeSide * side);
}

bool vcycle_pays(double jacobi_iterations, double vcycle_threshold) {
  return vcycle_threshold <= 0.0 || jacobi_iterations > vcycle_threshold;
}

double BlockSystem::jacobi_iterations_estimate() {
  return clothsim::jacobi_iterations_estimate(stiffness_ratio(), model_.rows, model_.cols);
}

void BlockSystem::setup_preconditioner() {
  StageTimer timer(profile_, StepStage::preconditioner_setup);
  if (multigrid_) {
    vcycle_ = vcycle_pays(jacobi_iterations_estimate(), vcycle_threshold_);
    if (vcycle_) {
      multigrid_->setup({row_offset, column, block, preconditioner, free, hold, held_normal, holding}, threads_);
    }
    return;
  }
  if (coarse_factor_.dofs() == 0) return;
  const std::size_t n = model_.particle_count();
  coarse_factor_.clear();
  // The lower triangle of P^T A P over the free particles; P sums each aggregate's particles.
  for (std::size_t p = 0; p < n; ++p) {
    if (!free[p]) continue;
    const std::size_t row_aggregate = particle_aggregate_[p];
    for (std::uint32_t k = row_offset[p]; k < row_offset[p + 1]; ++k) {
      const std::uint32_t q = column[k];
      if (!free[q]) continue;
      const std::size_t column_aggregate = particle_aggregate_[q];
      if (column_aggregate > row_aggregate) continue;
      const Mat3 b = holding ? held_block(block[k], hold[p], held_normal[p], hold[q], held_normal[q]) : block[k];
      for (int r = 0; r < 3; ++r) {
        const std::size_t i = 3 * row_aggregate + static_cast<std::size_t>(r);
        for (int c = 0; c < 3; ++c) {
          const std::size_t j = 3 * column_aggregate + static_cast<std::size_t>(c);
          if (j <= i) coarse_factor_.lower(i, j) += b(r, c);
        }
      }
    }
  }
  // Aggregates without free particles get an identity block (BandedCholesky::factor): their
  // right-hand side is always zero.
  coarse_factor_.factor();
}

}  // namespace clothsim
