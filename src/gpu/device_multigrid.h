// The multigrid V-cycle on the device: the preconditioner of implicit Euler's conjugate gradients
// (gpu/device_implicit_euler.h) on a lattice, the CPU's LatticeMultigrid (integrators/multigrid.h)
// with the same levels, transfer, Galerkin coarse matrices, sweeps (lines or single particles on
// level 0, integrator.cg_line_smoother) and exact coarsest solve. What differs is the order of the
// Gauss-Seidel sweeps: the CPU sweeps bands of rows (or lines), each band in order, which a GPU
// cannot do in parallel; here the nodes take 9 colours, (i mod 3, j mod 3), and the lines 3, no
// two of which share a matrix entry (the stencil reaches 2 nodes), and each colour is one pass
// (two for lines: multigrid_lines.comp). The CPU measured the same iterations with 9 colours as
// with its bands (multigrid.h).
//
// Per step, as named stages (docs/gpu.md, "Implicit Euler's multigrid on the device"):
//   multigrid_assemble  level 0: each particle's row of A = M + h (C + drag) + h^2 K in the
//                       lattice's stencil, from implicit_linearize's factors (the matrix-free
//                       products do not need it; the smoother and Galerkin's product do); the
//                       largest stiffness ratio, from which the host chooses the V-cycle or block
//                       Jacobi for the solve as the CPU does (BlockSystem::setup_preconditioner)
//   multigrid_galerkin  each coarse level's matrix P^T A P and its smoother's blocks, level by level
//   multigrid_coarse    the coarsest level's dense Cholesky factor (one workgroup)
//   multigrid_lines     with lines, each lattice row's and column's factor L D L^T
// and per CG iteration, z = V-cycle(r):
//   multigrid_cycle     z = 0; on level 0 2 sweeps of 9 colours (multigrid_lines: with lines, the
//                       rows then the columns, 3 colours each), the residual, its restriction;
//                       on each coarse level of more than kTailNodes nodes 1 sweep, the residual,
//                       the restriction (a pass each);
//   multigrid_coarse    the smaller levels down, the coarsest exactly, and back up, in one workgroup
//                       (their passes would cost more to start than to run);
//   multigrid_cycle     up again: the prolongation and the sweeps with the colours descending.
//
// Memory: every level's 21 blocks a node in single precision (the lattice's 13 would do on level
// 0; one layout for all levels keeps one pass per stage), about 1.15 kB a particle over all
// levels, and with lines 456 bytes a particle for their factors and vector.
#pragma once

#include <cstdint>
#include <vector>

#include "core/precision.h"
#include "gpu/buffer.h"
#include "gpu/compute_pipeline.h"
#include "gpu/device.h"
#include "gpu/shaders/multigrid_step.h"
#include "integrators/integrator.h"
#include "model/cloth_model.h"

namespace clothsim::gpu {

// What the V-cycle reads and writes of implicit Euler's arrays.
struct MultigridInputs {
  // The model (gpu/device_forces.h): the gather table, the elements' particles, masses, environment.
  const Buffer* gather_offset;
  const Buffer* gather_slot;
  const Buffer* connector_particles;
  const Buffer* radial_particles;
  const Buffer* particle_mass;
  const Buffer* environment;
  // The step's (gpu/device_implicit_euler.h): the element factors, anchors, holds, block Jacobi
  // inverses, the CG residual r and preconditioned residual z, the solve's scalars and counters.
  const Buffer* connector_factors;
  const Buffer* radial_factors;
  const Buffer* particle_anchor;
  const Buffer* hold;
  const Buffer* surface_contacts;
  const Buffer* jacobi;
  const Buffer* residual;
  const Buffer* preconditioned;
  const Buffer* solve_real;
  const Buffer* solve_uint;
};

class DeviceMultigrid {
 public:
  // Whether implicit Euler on the device preconditions with the V-cycle: on a lattice (rows and
  // cols filled in `counts`), with the CPU's settings that choose it (cg_two_level, cg_multigrid).
  static bool applies(const LatticeCounts& counts, const IntegratorSettings& settings);
  // Device memory of the levels for a rows x cols lattice, bytes.
  static std::uint64_t bytes_for(std::uint32_t rows, std::uint32_t cols, Precision precision, bool lines);

  // The levels of a rows x cols lattice whose model has `connectors` connectors (its radial springs'
  // force slots follow the connectors' two each). `lines`: level 0's smoother solves lines
  // (integrator.cg_line_smoother), else single particles.
  DeviceMultigrid(Device& device, std::uint32_t rows, std::uint32_t cols, std::uint32_t connectors,
                  Precision precision, bool lines);
  // Binds the passes to implicit Euler's arrays (again whenever one of them is replaced).
  void bind(const MultigridInputs& inputs);

  // Level 0's matrix and the stiffness ratio (into the solve's counters, kStiffnessRatio).
  void record_assemble(VkCommandBuffer commands) const;
  // The coarse levels' matrices and the coarsest factor, from level 0's.
  void record_setup(VkCommandBuffer commands) const;
  // preconditioned = V-cycle applied to residual. `iteration`: passes of a CG iteration, which
  // return at once once the solve has stopped.
  void record_apply(VkCommandBuffer commands, bool iteration) const;

 private:
  struct Level {
    std::uint32_t rows = 0;
    std::uint32_t cols = 0;
    std::uint32_t base = 0;  // the first node in the level arrays
    std::uint32_t nodes() const { return rows * cols; }
  };
  static std::vector<Level> levels_for(std::uint32_t rows, std::uint32_t cols);
  // The arrays' sizes for `levels`: the blocks, the smoother's blocks, each vector, the coarsest factor.
  struct LevelBytes {
    std::uint64_t blocks, diagonal_inverse, vector, factor;
  };
  static LevelBytes level_bytes(const std::vector<Level>& levels, Precision precision);
  // The push constants of a pass on level l (with level l + 1 as the next where there is one).
  MultigridPassConstants constants(std::uint32_t phase, std::size_t level, bool iteration) const;
  void sweep(VkCommandBuffer commands, std::size_t level, bool ascending, bool iteration) const;
  // One line sweep on level 0: the rows, then the columns (ascending), or the reverse.
  void line_sweep(VkCommandBuffer commands, bool ascending, bool iteration) const;
  // Level 0's sweeps on one side of the coarse correction: lines or single particles.
  void smooth_fine(VkCommandBuffer commands, bool ascending, bool iteration) const;
  // The line smoother's arrays: the factors of both directions, the vector of the line being solved.
  struct LineBytes {
    std::uint64_t factors, vector;
  };
  static LineBytes line_bytes(std::uint32_t rows, std::uint32_t cols, Precision precision);

  std::vector<Level> levels_;
  bool lines_ = false;    // level 0's smoother solves lines
  std::size_t tail_ = 1;  // the first level multigrid_coarse's one workgroup cycles over
  std::uint32_t radial_slot_base_;
  Buffer blocks_, diagonal_inverse_, rhs_, solution_, residual_, factor_, line_factors_, line_vector_;
  ComputePipeline assemble_pass_, galerkin_pass_, cycle_pass_, coarse_pass_, lines_pass_;
};

}  // namespace clothsim::gpu
