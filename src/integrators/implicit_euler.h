// Implicit (backward) Euler with one Newton step solved by conjugate gradients, after Baraff and
// Witkin, "Large Steps in Cloth Simulation" (SIGGRAPH 1998), sec. 3 and 5.
//
// Why. A real fabric is far stiffer in stretch than it is heavy: cotton at 128 x 128 particles
// has connector frequencies near 1e5 rad/s, so an explicit method needs steps of about 1e-5 s.
// Backward Euler is stable for any step on such stiff, damped problems, and takes the frame time
// 1/60 s as its step.
//
// The step. With h the step, M the masses, f0 = f(x0, v0), K = -df/dx and C = -df/dv at the start
// of the step (forces/element_jacobian.h), one Newton step of backward Euler,
//   v1 = v0 + dv,  x1 = x0 + h v1,  M dv = h f(x1, v1) linearised at (x0, v0),
// is the linear system
//   (M + h C + h^2 K) dv = h (f0 - h K v0)                              (Baraff-Witkin eq. 16)
// Anchored particles are constraints: their dv is known (the path's velocity at t + h minus v0),
// and their position change in the K term is the path's exact displacement, not h v1. Their rows
// are dropped and their columns moved to the right-hand side; conjugate gradients then runs on
// the free particles only, which is Baraff and Witkin's filtered PCG (sec. 5.3) with the filter
// S = 0 on anchored particles and I elsewhere. (Their partially constrained directions, S = I -
// p p^T, are not needed: an anchor fixes all three coordinates.)
//
// Particles resting on an obstacle (model/surface_contacts.h, filled by the collision
// stage) are held on its surface the same way (Baraff and Witkin's constrained particles, sec.
// 5.3; implicit_euler_contacts.cpp). One whose predicted end velocity v0 + h f0 / m moves into the
// surface is held:
//   sliding   along its contact normal n only: the normal part of its dv is fixed, so that it ends
//             moving with the surface along n, and the filter S = I - n n^T removes that direction
//             from the solve; the tangential directions stay free;
//   stuck     in all three directions (S = 0, it ends moving with the surface), when friction can
//             stop its slide and hold it against the tangential force within the step:
//             |m v_t / h + f_t| <= mu |f_n| (Coulomb's static friction).
// Its neighbours respond to it being held within the same solve. After the solve, the surface's
// impulse on it is A dv - b: a surface cannot pull, so particles with a negative normal impulse
// are let go and the system is solved once more (the preconditioner keeps the first set: its
// Jacobi blocks and its coarse matrix, P^T S A S P, are those of the system with the first set
// held); a stuck particle that needed more than mu times its normal impulse slides from the next
// step on (solving again for it took a second solve in most steps of a sheet on a table). The
// normal impulses are handed back to the obstacle pass, which turns them into Coulomb friction for
// the sliding particles. Without this, a particle pressed onto an obstacle moves into it within
// each step and is pushed back by the projection after it, which stretches its springs (cotton at
// 1 ms steps stored up to 66 J of connector energy that way in `pile`; docs/collisions.md).
//
// The matrix. A = M + h C + h^2 K is stored as a block-sparse matrix (CSR of 3x3 blocks) following
// the lattice's particle adjacency: particle p couples to itself, its 4 connector neighbours, the
// 4 diagonal neighbours through adjacent radial springs and the 4 particles two away through
// opposite ones, 13 blocks in the interior. It is assembled once per step and multiplied 10 to
// 300 times by CG. Rejected: matrix-free products, which re-evaluate every element per CG
// iteration (about 30 doubles of element data per radial spring, each read by 3 particles) and
// need a scatter-then-gather per product to stay deterministic; the assembled row costs 117
// doubles read once per product and no scatter.
//
// Assembly is deterministic: a first pass computes every element's Jacobian into its own slot
// (in parallel over elements), a second pass builds each particle's block row by visiting the
// particle's elements in the fixed order of the force gather table (in parallel over rows; a row
// is written by one thread only). The right-hand side and the block-diagonal (Jacobi)
// preconditioner come out of the same row pass.
//
// Conjugate gradients: started from the previous step's dv (Baraff and Witkin's warm start),
// stopped when |r| <= cg_tolerance |b| over the free coordinates or after cg_max_iterations (the
// step is then taken with the last iterate and counted in IntegratorStats::cg_unconverged_solves).
// Dot products are sums over fixed blocks of particles added in block order, so the result is
// bit-for-bit the same for any thread count.
//
// Preconditioner. The base is block Jacobi, the inverses of the 3x3 diagonal blocks. On a stiff
// fabric it is not enough: the in-plane stretch part of A is a stiff lattice Laplacian, whose
// condition number grows with the square of the lattice size, and Jacobi-preconditioned CG took
// about 420 iterations per step on 32 x 32 cotton and 480 on 64 x 64 (docs/performance.md). With
// cg_two_level (the default) a coarse-grid correction is added, and with cg_multigrid (the
// default too) it is a multigrid V-cycle (integrators/multigrid.h): bilinear interpolation
// between lattice levels halved in each direction, Galerkin coarse matrices P^T A P down to 8 x 8
// nodes solved exactly, block Gauss-Seidel smoothing in fixed bands of rows, symmetric; the whole
// preconditioner is the V-cycle (block Jacobi is its smoother's diagonal). On cotton at the frame
// step it takes 14 iterations per step at 64 x 64 and 128 x 128 (most 18 and 19) against 89 for
// the aggregates below; per step it costs about as much on one thread and 20 % less on two at
// 128 x 128 (its loops are all parallel), and more at 1 ms steps on small sheets, where few
// iterations are needed anyway (docs/performance.md). Without
// cg_multigrid, the free particles are grouped into aggregates of 4 x 4, P sums a vector over
// each aggregate, and the preconditioner is the additive two-level one
//   M^-1 = D^-1 + P (P^T A P)^-1 P^T
// (unsmoothed aggregation; see Tamstorf, Jones and McCormick, "Smoothed aggregation multigrid for
// cloth simulation", SIGGRAPH Asia 2015). The coarse matrix P^T A P is banded (aggregates couple
// to their 8 neighbours) and is factored by a banded Cholesky (integrators/banded_cholesky.h)
// once per step; applying it costs two band solves, serial. It brings the iterations to about 89
// per step at 128 x 128, independent of the lattice size; its factor grows as particles x cols.
// Both are symmetric positive definite, so CG still applies; at very tight tolerances (1e-10) on
// small lattices the aggregates can need more iterations than Jacobi alone, since
// piecewise-constant aggregates give coarse functions with stiff jumps at their borders (which
// interpolation avoids).
//
// Energy bookkeeping. The work integrals of ClothState take the powers at the end of the step,
// (x1, v1), times h: a backward-Euler quadrature of the work, first order like the method. The
// forces evaluated there for the powers are reused as f0 of the next step when the state has
// not been changed in between. Backward Euler also dissipates energy numerically (about
// h omega^2 per unit time in a mode of frequency omega, much more in the stiff modes), so the
// energy balance E(t) - (E(0) + W) is not a check of accuracy for this method: it is the
// numerical dissipation, and it is negative.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/mat3.h"
#include "forces/element_jacobian.h"
#include "forces/forces.h"
#include "integrators/banded_cholesky.h"
#include "integrators/held_directions.h"
#include "integrators/integrator.h"
#include "integrators/multigrid.h"
#include "model/gather_table.h"

namespace clothsim {

class ImplicitEuler final : public Integrator {
 public:
  ImplicitEuler(const ClothModel& model, const IntegratorSettings& settings, const ForceOptions& options);
  IntegratorKind kind() const override { return IntegratorKind::implicit_euler; }
  StepOutcome step(ClothState& state, double t_limit) override;
  std::size_t workspace_bytes() const override;
  // The bytes workspace_bytes() reports on the lattice build_lattice() makes with `counts` (at
  // least 5 x 5; smaller ones may need less), besides the force buffers
  // (ForceBuffers::bytes_for): element Jacobians, the block matrix (13 blocks per interior
  // particle), the CG vectors, and with cg_two_level the coarse matrix's banded factor, which
  // grows as particles x cols (sim/memory_estimate.h).
  static std::size_t workspace_bytes_for(const LatticeCounts& counts, const IntegratorSettings& settings);

  // Block-sparse structure of the system matrix, for tests: row p's blocks are
  // [row_offset()[p], row_offset()[p + 1]) with columns column()[k], ascending.
  const std::vector<std::uint32_t>& row_offset() const { return row_offset_; }
  const std::vector<std::uint32_t>& column() const { return column_; }
  // CG iterations of the last step.
  int last_iterations() const { return last_iterations_; }
  // The statistics, the warm start of the next solve (the last step's velocity change) and which
  // particles slipped on their surface in the last step.
  void transfer_state(StateArchive& archive) override;

 private:
  struct Powers {
    double damping = 0.0;
    double drag = 0.0;
    double anchor = 0.0;
  };
  // f(x, v) into force_ and the powers at (time, x, v); anchored particles must be on their path.
  Powers evaluate(double time, std::span<const Vec3> position, std::span<const Vec3> velocity);
  void compute_element_jacobians(const ClothState& state);
  void assemble(double h);
  // Solves A dv = b over the free particles, the held directions excluded; returns the iterations taken.
  int solve();
  // The index of row p's diagonal block in block_.
  std::uint32_t diagonal_block(std::size_t p) const;
  // Row p of A times `vector`.
  Vec3 row_product(std::size_t p, const std::vector<Vec3>& vector) const;
  // Surface contacts (model/surface_contacts.h): which particles the step holds on their
  // surface, with the normal part of their dv set; after a solve, lets go of those the surface
  // would have to pull (returns whether any); after the step, the impulses and their work.
  // (implicit_euler_contacts.cpp)
  void hold_on_surfaces(const ClothState& state, double h);
  bool release_held_particles();
  void book_surface_impulses(ClothState& state);
  void set_hold(std::size_t p, Hold hold, const Vec3& normal);
  // v with the held directions of particle p removed (the filter S_p: I - n n^T held along the
  // normal, 0 stuck); v where not held.
  Vec3 held(std::size_t p, const Vec3& v) const { return holding_ ? held_vector(hold_[p], held_normal_[p], v) : v; }
  // preconditioned_ = M^-1 residual_ (zero on anchored particles); returns residual . preconditioned.
  double precondition();
  // The coarse-grid correction for this step's system (and held set): the aggregates' coarse
  // matrix P^T A P and its factor, or the multigrid hierarchy.
  void assemble_coarse();

  const ClothModel& model_;
  IntegratorSettings settings_;
  ForceOptions options_;
  int threads_ = 1;

  // Forces.
  ForceBuffers buffers_;
  std::vector<Vec3> force_;  // [particle_count()], N, at evaluated_*
  // The state the forces in force_ belong to, to reuse them as the next step's f0.
  std::vector<Vec3> evaluated_position_;  // [particle_count()]
  std::vector<Vec3> evaluated_velocity_;  // [particle_count()]
  double evaluated_time_ = -1.0;
  bool evaluated_valid_ = false;

  // Element Jacobians at the start of the step.
  std::vector<element::ConnectorJacobian> connector_jacobian_;  // [connector_count()]
  std::vector<element::RadialJacobian> radial_jacobian_;        // [radial_count()]

  // Each particle's element slots: the order in which its block row is assembled.
  GatherTable gather_;

  // System matrix (CSR of 3x3 blocks) and where each element slot adds its blocks: slot s of a
  // connector adds to blocks connector_block_[s][j], j over its 2 particles; likewise radial.
  std::vector<std::uint32_t> row_offset_;                      // [particle_count() + 1]
  std::vector<std::uint32_t> column_;                          // [blocks]
  std::vector<Mat3> block_;                                    // [blocks], A = M + h C + h^2 K
  std::vector<std::array<std::uint32_t, 2>> connector_block_;  // [2 connector_count()]
  std::vector<std::array<std::uint32_t, 3>> radial_block_;     // [3 radial_count()]
  std::vector<Mat3> preconditioner_;  // [particle_count()], inverse diagonal blocks (0 if anchored)
  std::vector<std::uint8_t> free_;    // [particle_count()], 1 for integrated particles
  std::uint64_t revision_ = 0;        // model revision free_ and the reused forces were made for

  // Right-hand side and CG vectors [particle_count()].
  std::vector<Vec3> displacement_;  // z: h v0 (free) or the anchor path's displacement, m
  std::vector<Vec3> rhs_;           // b, N s
  std::vector<Vec3> dv_;            // the unknown, m/s; anchored entries hold their known values
  std::vector<Vec3> residual_;
  std::vector<Vec3> preconditioned_;
  std::vector<Vec3> direction_;
  std::vector<Vec3> product_;
  // Coarse-grid correction (cg_two_level): with cg_multigrid the V-cycle's hierarchy; without,
  // the aggregate of each particle and the coarse matrix's banded Cholesky factor (3 unknowns per
  // aggregate; none without the correction).
  std::optional<LatticeMultigrid> multigrid_;
  std::vector<std::uint32_t> particle_aggregate_;  // [particle_count()]
  BandedCholesky coarse_factor_;
  std::vector<double> coarse_vector_;  // [coarse_factor_.dofs()]

  std::vector<double> block_sum_a_;  // per-block partial sums of the reductions
  std::vector<double> block_sum_b_;
  std::vector<double> block_sum_c_;
  int last_iterations_ = 0;

  // Particles held on an obstacle's surface this step: how, and their unit normal (zero where not held).
  std::vector<Hold> hold_;             // [particle_count()]
  std::vector<std::uint8_t> slipped_;  // [particle_count()] 1: held stuck by more than Coulomb's friction last step
  std::vector<Vec3> held_normal_;      // [particle_count()]
  bool holding_ = false;               // some particle is held this step
};

}  // namespace clothsim
