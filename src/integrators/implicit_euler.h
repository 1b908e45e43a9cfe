// Implicit (backward) Euler with one Newton step solved by conjugate gradients, after Baraff and
// Witkin, "Large Steps in Cloth Simulation" (SIGGRAPH 1998), sec. 3 and 5. A real fabric is far
// stiffer in stretch than it is heavy (cotton at 128 x 128 has connector frequencies near 1e5
// rad/s, so an explicit method needs steps of about 1e-5 s); backward Euler is stable for any
// step on such stiff, damped problems, and takes the frame time 1/60 s as its step.
//
// The step. With h the step, M the masses, f0 = f(x0, v0), K = -df/dx and C = -df/dv at the start
// of the step (forces/element_jacobian.h), one Newton step of backward Euler,
//   v1 = v0 + dv,  x1 = x0 + h v1,  M dv = h f(x1, v1) linearised at (x0, v0),
// is the linear system
//   (M + h C + h^2 K) dv = h (f0 - h K v0)                              (Baraff-Witkin eq. 16)
// Anchored particles are constraints: their dv is known (the path's velocity at t + h minus v0),
// their rows are dropped and their columns moved to the right-hand side (Baraff and Witkin's
// filtered PCG, sec. 5.3, with S = 0 on anchored particles). Particles resting on an obstacle
// (model/surface_contacts.h) are held the same way, along their contact normal when sliding and
// in all three directions when static friction holds them (implicit_euler_contacts.cpp); the
// surface's impulses go back to the obstacle pass for Coulomb friction.
//
// The matrix A = M + h C + h^2 K is block-sparse (CSR of 3x3 blocks, 13 per interior row),
// assembled once per step in two deterministic passes (every element's Jacobian into its own
// slot, then each particle's row in the gather table's order). CG starts from the previous step's
// dv and stops at |r| <= cg_tolerance |b| or after cg_max_iterations (counted in
// IntegratorStats::cg_unconverged_solves); its dot products are summed over fixed blocks, so the
// result is the same bit for bit for any thread count. The preconditioner is a multigrid V-cycle
// on the lattice (integrators/multigrid.h; cg_multigrid), or block Jacobi plus an exact
// coarse-grid correction on 4 x 4 aggregates (banded_cholesky.h; cg_two_level without
// cg_multigrid), or block Jacobi alone.
//
// The work integrals take the powers at the end of the step, (x1, v1), times h: first order like
// the method. Backward Euler dissipates energy numerically, so the energy balance is not an
// accuracy check for this method: it is the numerical dissipation, and it is negative.
//
// docs/model.md ("Implicit Euler") has the contacts, the matrix, the preconditioners and what was
// rejected in full; docs/performance.md the measurements.
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
