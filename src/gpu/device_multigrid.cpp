#include "gpu/device_multigrid.h"

#include "core/assert.h"
#include "gpu/real_arrays.h"
#include "gpu/shaders/implicit_step.h"
#include "gpu/shaders/multigrid_step.h"
#include "integrators/multigrid.h"

namespace clothsim::gpu {
namespace {

static_assert(LatticeMultigrid::kCoarsestNodes == kCoarsestNodes && LatticeMultigrid::kCoarseSweeps == kCoarseSweeps,
              "the shaders' levels and sweeps are LatticeMultigrid's");

ComputePipeline make_pass(Device& device, const char* name, Precision precision, std::uint32_t bindings,
                          std::uint32_t workgroup = 64) {
  return shader_pipeline(device, name, precision, bindings, sizeof(MultigridPassConstants), workgroup);
}

}  // namespace

std::vector<DeviceMultigrid::Level> DeviceMultigrid::levels_for(std::uint32_t rows, std::uint32_t cols) {
  // LatticeMultigrid's levels: halved (rounding up) until kCoarsestNodes nodes or fewer, at least one coarse level.
  std::vector<Level> levels{{rows, cols, 0}};
  do {
    const Level& last = levels.back();
    levels.push_back({(last.rows + 1) / 2, (last.cols + 1) / 2, last.base + last.nodes()});
  } while (levels.back().nodes() > LatticeMultigrid::kCoarsestNodes);
  return levels;
}

bool DeviceMultigrid::applies(const LatticeCounts& counts, const IntegratorSettings& settings) {
  return settings.cg_two_level && settings.cg_multigrid && counts.rows > 0 && counts.cols > 0 &&
         counts.rows * counts.cols == counts.particles;
}

DeviceMultigrid::LevelBytes DeviceMultigrid::level_bytes(const std::vector<Level>& levels, Precision precision) {
  const std::uint64_t real = real_size(precision);
  const std::uint64_t nodes = levels.back().base + levels.back().nodes();
  const std::uint64_t coarsest_dofs = 3 * std::uint64_t{levels.back().nodes()};
  // The blocks in single precision, as the CPU stores its levels (integrators/stencil_matrix.h).
  return {nodes * LatticeMultigrid::kStencil * 9 * sizeof(float), nodes * 9 * real, nodes * 3 * real,
          coarsest_dofs * coarsest_dofs * real};
}

std::uint64_t DeviceMultigrid::bytes_for(std::uint32_t rows, std::uint32_t cols, Precision precision, bool lines) {
  const LevelBytes bytes = level_bytes(levels_for(rows, cols), precision);
  return bytes.blocks + bytes.diagonal_inverse + 3 * bytes.vector + bytes.factor +
         (lines ? line_bytes(rows, cols, precision).factors + line_bytes(rows, cols, precision).vector : 0);
}

DeviceMultigrid::LineBytes DeviceMultigrid::line_bytes(std::uint32_t rows, std::uint32_t cols, Precision precision) {
  // Per particle and direction 3 blocks (D^-1, L1, L2), and one vector for the line being solved.
  const std::uint64_t nodes = std::uint64_t{rows} * cols;
  return {2 * nodes * 3 * 9 * real_size(precision), nodes * 3 * real_size(precision)};
}

DeviceMultigrid::DeviceMultigrid(Device& device, std::uint32_t rows, std::uint32_t cols, std::uint32_t connectors,
                                 Precision precision, bool lines)
    : levels_(levels_for(rows, cols)),
      lines_(lines),
      radial_slot_base_(2 * connectors),
      blocks_(device, level_bytes(levels_, precision).blocks, Memory::device_local),
      diagonal_inverse_(device, level_bytes(levels_, precision).diagonal_inverse, Memory::device_local),
      rhs_(device, level_bytes(levels_, precision).vector, Memory::device_local),
      solution_(device, rhs_.bytes(), Memory::device_local),
      residual_(device, rhs_.bytes(), Memory::device_local),
      factor_(device, level_bytes(levels_, precision).factor, Memory::device_local),
      // Without lines, placeholders that the line pass is bound to but never reads.
      line_factors_(device, lines ? line_bytes(rows, cols, precision).factors : 16, Memory::device_local),
      line_vector_(device, lines ? line_bytes(rows, cols, precision).vector : 16, Memory::device_local),
      assemble_pass_(make_pass(device, "multigrid_assemble", precision, 14)),
      galerkin_pass_(make_pass(device, "multigrid_galerkin", precision, 2)),
      cycle_pass_(make_pass(device, "multigrid_cycle", precision, 12)),
      coarse_pass_(make_pass(device, "multigrid_coarse", precision, 7, kCoarseWorkgroup)),
      lines_pass_(make_pass(device, "multigrid_lines", precision, 9)) {
  CLOTHSIM_ASSERT(levels_.size() >= 2 && levels_.size() <= kMaxLevels, "at least one coarse level");
  // The first coarse level small enough for one workgroup, or the coarsest.
  tail_ = 1;
  while (tail_ + 1 < levels_.size() && levels_[tail_].nodes() > kTailNodes) ++tail_;
}

void DeviceMultigrid::bind(const MultigridInputs& in) {
  assemble_pass_.bind(std::vector<const Buffer*>{in.gather_offset, in.gather_slot, in.connector_particles,
                                                 in.radial_particles, in.connector_factors, in.radial_factors,
                                                 in.particle_mass, in.environment, in.particle_anchor, in.solve_real,
                                                 in.solve_uint, in.hold, in.surface_contacts, &blocks_});
  galerkin_pass_.bind(std::vector<const Buffer*>{&blocks_, &diagonal_inverse_});
  cycle_pass_.bind(std::vector<const Buffer*>{&blocks_, &diagonal_inverse_, in.jacobi, &rhs_, &solution_, &residual_,
                                              in.residual, in.preconditioned, in.particle_anchor, in.hold,
                                              in.surface_contacts, in.solve_uint});
  coarse_pass_.bind(
      std::vector<const Buffer*>{&blocks_, &diagonal_inverse_, &rhs_, &solution_, &residual_, &factor_, in.solve_uint});
  lines_pass_.bind(std::vector<const Buffer*>{&blocks_, &line_factors_, &line_vector_, in.residual, in.preconditioned,
                                              in.particle_anchor, in.hold, in.surface_contacts, in.solve_uint});
}

MultigridPassConstants DeviceMultigrid::constants(std::uint32_t phase, std::size_t level, bool iteration) const {
  const Level& here = levels_[level];
  const Level next = level + 1 < levels_.size() ? levels_[level + 1] : Level{};
  return MultigridPassConstants{phase,
                                static_cast<std::uint32_t>(level),
                                here.base,
                                here.rows,
                                here.cols,
                                next.base,
                                next.rows,
                                next.cols,
                                0u,
                                0u,
                                iteration ? 1u : 0u,
                                radial_slot_base_};
}

void DeviceMultigrid::record_assemble(VkCommandBuffer commands) const {
  const MultigridPassConstants pass = constants(0, 0, false);
  assemble_pass_.dispatch(commands, &pass, levels_[0].nodes());
}

void DeviceMultigrid::record_setup(VkCommandBuffer commands) const {
  for (std::size_t level = 0; level + 1 < levels_.size(); ++level) {
    const MultigridPassConstants pass = constants(0, level, false);
    galerkin_pass_.dispatch(commands, &pass, levels_[level + 1].nodes());
  }
  const MultigridPassConstants pass = constants(kCoarseFactor, levels_.size() - 1, false);
  coarse_pass_.dispatch(commands, &pass, kCoarseWorkgroup);
  if (!lines_) return;
  for (std::uint32_t direction = 0; direction < 2; ++direction) {
    MultigridPassConstants factor = constants(kLinesFactor, 0, false);
    factor.direction = direction;
    lines_pass_.dispatch(commands, &factor, direction == 0 ? levels_[0].rows : levels_[0].cols);
  }
}

void DeviceMultigrid::line_sweep(VkCommandBuffer commands, bool ascending, bool iteration) const {
  // Down the V the rows then the columns, colours ascending; up it the reverse (multigrid_lines.comp).
  for (std::uint32_t k = 0; k < 2 * kLineColours; ++k) {
    const std::uint32_t step = ascending ? k : 2 * kLineColours - 1 - k;
    MultigridPassConstants pass = constants(kLinesRhs, 0, iteration);
    pass.direction = step / kLineColours;
    pass.colour = step % kLineColours;
    const std::uint32_t lines = pass.direction == 0 ? levels_[0].rows : levels_[0].cols;
    const std::uint32_t length = pass.direction == 0 ? levels_[0].cols : levels_[0].rows;
    const std::uint32_t colour_lines = (lines + kLineColours - 1 - pass.colour) / kLineColours;
    if (colour_lines == 0) continue;
    lines_pass_.dispatch(commands, &pass, colour_lines * length);
    pass.phase = kLinesSolve;
    lines_pass_.dispatch(commands, &pass, colour_lines);
  }
}

void DeviceMultigrid::smooth_fine(VkCommandBuffer commands, bool ascending, bool iteration) const {
  if (lines_) {
    for (int s = 0; s < LatticeMultigrid::kFineLineSweeps; ++s) line_sweep(commands, ascending, iteration);
  } else {
    for (int s = 0; s < LatticeMultigrid::kFineSweeps; ++s) sweep(commands, 0, ascending, iteration);
  }
}

void DeviceMultigrid::sweep(VkCommandBuffer commands, std::size_t level, bool ascending, bool iteration) const {
  const Level& here = levels_[level];
  for (std::uint32_t k = 0; k < kSmootherColours; ++k) {
    MultigridPassConstants pass = constants(kCycleSmooth, level, iteration);
    pass.colour = ascending ? k : kSmootherColours - 1 - k;
    const std::uint32_t colour_rows = (here.rows + 2 - pass.colour / 3) / 3;
    const std::uint32_t colour_cols = (here.cols + 2 - pass.colour % 3) / 3;
    if (colour_rows * colour_cols > 0) cycle_pass_.dispatch(commands, &pass, colour_rows * colour_cols);
  }
}

void DeviceMultigrid::record_apply(VkCommandBuffer commands, bool iteration) const {
  const auto pass = [&](std::uint32_t phase, std::size_t level, std::uint32_t invocations) {
    const MultigridPassConstants values = constants(phase, level, iteration);
    cycle_pass_.dispatch(commands, &values, invocations);
  };
  // Down: level 0 from zero, each coarse level from zero (the restriction clears it).
  pass(kCycleClear, 0, levels_[0].nodes());
  for (std::size_t level = 0; level < tail_; ++level) {
    if (level == 0) {
      smooth_fine(commands, true, iteration);
    } else {
      for (int s = 0; s < LatticeMultigrid::kCoarseSweeps; ++s) sweep(commands, level, true, iteration);
    }
    pass(kCycleResidual, level, levels_[level].nodes());
    pass(kCycleRestrict, level, levels_[level + 1].nodes());
  }
  // The small levels and the coarsest, down and up, in one workgroup.
  const MultigridPassConstants small = constants(kCoarseCycle, tail_, iteration);
  coarse_pass_.dispatch(commands, &small, kCoarseWorkgroup);
  // Up: the correction, then the sweeps in the reverse order.
  for (std::size_t level = tail_; level-- > 0;) {
    pass(kCycleProlong, level, levels_[level].nodes());
    if (level == 0) {
      smooth_fine(commands, false, iteration);
    } else {
      for (int s = 0; s < LatticeMultigrid::kCoarseSweeps; ++s) sweep(commands, level, false, iteration);
    }
  }
}

}  // namespace clothsim::gpu
