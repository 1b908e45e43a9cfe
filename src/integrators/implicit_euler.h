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
// The matrix A = M + h C + h^2 K, its assembly, CG and preconditioners are the BlockSystem's
// (integrators/block_system.h), shared with the IMEX pair. CG starts from the previous step's dv
// and stops at |r| <= cg_tolerance |b| or after cg_max_iterations (counted in
// IntegratorStats::cg_unconverged_solves).
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
#include "forces/forces.h"
#include "integrators/block_system.h"
#include "integrators/integrator.h"

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
  const std::vector<std::uint32_t>& row_offset() const { return system_.row_offset; }
  const std::vector<std::uint32_t>& column() const { return system_.column; }
  // CG iterations of the last step.
  int last_iterations() const { return last_iterations_; }
  // Whether the last step's solve took the multigrid V-cycle (BlockSystem::setup_preconditioner).
  bool last_solve_took_vcycle() const { return system_.vcycle_chosen(); }
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
  // The system's right-hand side b = h (f0 - K z) after assembly (which leaves K z in it).
  void form_rhs(double h);
  // Solves A dv = b, counting a solve that stops at cg_max_iterations; returns the iterations.
  int solve();
  // Surface contacts (model/surface_contacts.h): which particles the step holds on their
  // surface, with the normal part of their dv set; after a solve, lets go of those the surface
  // would have to pull (returns whether any); after the step, the impulses and their work.
  // (implicit_euler_contacts.cpp)
  void hold_on_surfaces(const ClothState& state, double h);
  bool release_held_particles();
  void book_surface_impulses(ClothState& state);

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

  // A = M + h C + h^2 K, its solve and preconditioner; its unknown is dv (anchored entries hold
  // their known values), its right-hand side b.
  BlockSystem system_;
  std::uint64_t revision_ = 0;      // model revision the free set and the reused forces were made for
  std::vector<Vec3> displacement_;  // [particle_count()], z: h v0 (free) or the anchor path's displacement, m
  int last_iterations_ = 0;
  std::vector<std::uint8_t> slipped_;  // [particle_count()] 1: held stuck by more than Coulomb's friction last step
};

}  // namespace clothsim
