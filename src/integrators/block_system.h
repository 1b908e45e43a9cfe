// The linear system in the particles' velocities that the implicit integrators solve, A u = b with
// A = M + a C + k K (+ a drag on the diagonal): implicit Euler's Newton step (a = h, k = h^2,
// integrators/implicit_euler.h) and each implicit stage of the IMEX pair (a = gamma h, k = 0,
// integrators/imex.h). One copy of the machinery both use:
//
//   * the element Jacobians K = -df/dx and C = -df/dv (forces/element_jacobian.h), per element;
//   * the block-sparse matrix: CSR of 3x3 blocks over the particle pairs an element joins (13 per
//     interior row), assembled in two deterministic passes (each element's Jacobian into its own
//     slot, then each particle's row in the gather table's order);
//   * preconditioned conjugate gradients over the free particles, anchored rows dropped and their
//     known columns moved to the right-hand side, held directions (held_directions.h) filtered,
//     with its reductions summed over fixed blocks: the same bits for any thread count;
//   * the preconditioner: the multigrid V-cycle (multigrid.h; cg_multigrid), block Jacobi plus an
//     exact coarse solve on 4 x 4 aggregates (banded_cholesky.h; cg_two_level alone), or Jacobi.
//
// The integrator owns the right-hand side and the meaning of the unknown (implicit Euler's dv, the
// IMEX stage velocity); the system only reads b and starts CG from the unknown's current value,
// which is how each caller warm-starts it.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/mat3.h"
#include "core/step_profile.h"
#include "forces/element_jacobian.h"
#include "forces/forces.h"
#include "integrators/banded_cholesky.h"
#include "integrators/held_directions.h"
#include "integrators/integrator.h"
#include "integrators/multigrid.h"
#include "model/gather_table.h"

namespace clothsim {

// Block Jacobi's CG iterations per solve at the default tolerance, roughly, for a system of
// stiffness ratio s (BlockSystem::stiffness_ratio) on a rows x cols lattice: min(sqrt(s),
// 6.5 max(rows, cols)). Its condition number grows with s until the lattice bounds it (the
// smoothest mode's stiffness falls as the lattice's side squared). Fitted on the built-in scenes
// (docs/performance.md, "A cheaper implicit Euler step"), within a factor of about 1.5.
double jacobi_iterations_estimate(double stiffness_ratio, int rows, int cols);
// Whether a solve takes the V-cycle rather than block Jacobi: where block Jacobi's estimate is
// above IntegratorSettings::cg_vcycle_threshold (always, for a threshold of 0).
bool vcycle_pays(double jacobi_iterations, double vcycle_threshold);

class BlockSystem {
 public:
  // Times its parts (jacobians, assembly, preconditioner setup, linear solve) into `profile`, the
  // integrator's, which outlives it.
  BlockSystem(const ClothModel& model, const IntegratorSettings& settings, int threads, StepProfile& profile);

  // Marks the anchored particles as outside the system (after a model edit).
  void update_free();
  // The element Jacobians at (x, v) for the force terms in `terms`.
  void compute_jacobians(ForceTerms terms, std::span<const Vec3> x, std::span<const Vec3> v);
  // A = M + damping_scale (C + drag I) + stiffness_scale K from the element Jacobians, with the
  // block Jacobi preconditioner; anchored rows are zero. With `displacement` (size n, else empty),
  // also stiffness_product[p] = (K z)_p for the free particles, z = displacement.
  void assemble(ForceTerms terms, double damping_scale, double stiffness_scale, std::span<const Vec3> displacement,
                std::span<Vec3> stiffness_product);
  // The coarse-grid correction for this matrix and held set (multigrid levels or aggregate factor).
  // With the multigrid, a system that block Jacobi alone solves in fewer passes over the matrix
  // than the V-cycle's setup and iterations cost (a mass-dominated one: small steps, soft sheets,
  // an IMEX stage's damping, a small lattice) is left to block Jacobi for this solve:
  // jacobi_iterations_estimate() at most IntegratorSettings::cg_vcycle_threshold.
  void setup_preconditioner();
  // Whether the preconditioner may be the multigrid V-cycle, whose levels depend on the held set.
  bool uses_multigrid() const { return multigrid_.has_value(); }
  // Whether the last setup_preconditioner() chose the V-cycle.
  bool vcycle_chosen() const { return multigrid_.has_value() && vcycle_; }
  // The system's stiffness relative to its mass: the largest over the free particles of
  // s = (trace A_pp - 3 m_p) / m_p, what the step's damping and stiffness add to the diagonal.
  double stiffness_ratio();
  // jacobi_iterations_estimate(stiffness_ratio(), rows, cols) for the model's lattice.
  double jacobi_iterations_estimate();
  struct Solve {
    int iterations = 0;
    bool converged = true;  // false: stopped at max_iterations
  };
  // Solves A u = rhs over the free particles from u's current value (anchored entries hold their
  // known values), until |r| <= max(relative |rhs|, absolute) or max_iterations.
  Solve solve(double relative, double absolute, int max_iterations);
  // (C v)_p + drag v_p, C the damping part of the last compute_jacobians(), matrix-free from the
  // element Jacobians (independent of the matrix's scales): minus the damping and drag force at
  // velocities v for the Jacobians' positions, N.
  Vec3 damping_product(std::size_t p, std::span<const Vec3> v, double drag) const;
  // Row p of A times `vector`.
  Vec3 row_product(std::size_t p, std::span<const Vec3> vector) const;
  // The index of row p's diagonal block in block.
  std::uint32_t diagonal_block(std::size_t p) const;
  // Holds particle p in the directions `hold` (normal: unit vector), with its preconditioner block.
  void set_hold(std::size_t p, Hold hold, const Vec3& normal);
  // v with the held directions of particle p removed; v where not held.
  Vec3 held(std::size_t p, const Vec3& v) const { return holding ? held_vector(hold[p], held_normal[p], v) : v; }

  std::size_t bytes() const;
  // bytes() on the lattice build_lattice() makes with `counts` (at least 5 x 5).
  static std::size_t bytes_for(const LatticeCounts& counts, const IntegratorSettings& settings);

  // The unknown and the right-hand side [particle_count()].
  std::vector<Vec3> solution;
  std::vector<Vec3> rhs;
  // The matrix (CSR of 3x3 blocks) and where each element slot adds its blocks: slot s of a
  // connector adds to blocks connector_block[s][j], j over its 2 particles; likewise radial.
  std::vector<std::uint32_t> row_offset;                      // [particle_count() + 1]
  std::vector<std::uint32_t> column;                          // [blocks], ascending within a row
  std::vector<Mat3> block;                                    // [blocks], A
  std::vector<std::array<std::uint32_t, 2>> connector_block;  // [2 connector_count()]
  std::vector<std::array<std::uint32_t, 3>> radial_block;     // [3 radial_count()]
  std::vector<Mat3> preconditioner;  // [particle_count()], inverse diagonal blocks (0 if anchored)
  std::vector<std::uint8_t> free;    // [particle_count()], 1 for the particles solved for
  // Element Jacobians of the last compute_jacobians().
  std::vector<element::ConnectorJacobian> connector_jacobian;  // [connector_count()]
  std::vector<element::RadialJacobian> radial_jacobian;        // [radial_count()]
  // Particles held on an obstacle's surface: how, and their unit normal (zero where not held).
  std::vector<Hold> hold;         // [particle_count()]
  std::vector<Vec3> held_normal;  // [particle_count()]
  bool holding = false;           // some particle is held

 private:
  // preconditioned_ = P^-1 residual_ (zero on anchored particles); returns residual . preconditioned.
  double precondition();
  template <typename Body>
  std::array<double, 3> blocked_sums(Body&& body);
  // Asks the cache for the element Jacobians row p (if any) will read.
  void prefetch_jacobians(std::size_t p) const;
  // What assemble() forms each row with.
  struct RowAssembly {
    double damping_scale;
    double stiffness_scale;
    double drag;  // N s/m, 0 without air drag
    std::span<const Vec3> displacement;
    std::span<Vec3> stiffness_product;
  };
  // Row p of the matrix, its preconditioner block, and with a displacement (K z)_p.
  void assemble_row(std::size_t p, const RowAssembly& row);

  const ClothModel& model_;
  int threads_ = 1;
  StepProfile& profile_;
  GatherTable gather_;  // each particle's element slots: the order its row is assembled in
  std::vector<Vec3> residual_;
  std::vector<Vec3> preconditioned_;
  std::vector<Vec3> direction_;
  std::vector<Vec3> product_;
  // Coarse-grid correction: the V-cycle's hierarchy, or each particle's aggregate and the coarse
  // matrix's banded Cholesky factor (3 unknowns per aggregate; none without the correction).
  std::optional<LatticeMultigrid> multigrid_;
  double vcycle_threshold_ = 0.0;                  // IntegratorSettings::cg_vcycle_threshold
  bool vcycle_ = true;                             // the last setup chose the V-cycle (with multigrid_)
  std::vector<std::uint32_t> particle_aggregate_;  // [particle_count()]
  BandedCholesky coarse_factor_;
  std::vector<double> coarse_vector_;  // [coarse_factor_.dofs()]
  std::vector<double> block_sum_a_;    // per-block partial sums of the reductions
  std::vector<double> block_sum_b_;
  std::vector<double> block_sum_c_;
};

}  // namespace clothsim
