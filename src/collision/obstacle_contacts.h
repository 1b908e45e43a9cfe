// The collision stage's obstacle pass (issue 8): particles against the model's colliders,
// between accepted steps (docs/collisions.md).
//
// Design: a projection plus a velocity correction on the accepted state, after the step and
// before the events, instead of a contact force inside the derivative. The explicit integrators
// never see a contact, so every one of them (RKF45's error control included) integrates smooth
// stages, and a contact is resolved exactly to the thickness at every step end; implicit Euler
// also holds resting particles on their surface within its step (below). Rejected: penalty
// forces, whose stiffness would set RKF45's step size everywhere near an obstacle, and which
// leave particles inside by an amount that depends on the load.
//
// For each free particle and each collider, in collider index order, with the collider at the
// step's end time t1:
//   1. sweep     the segment from the particle's position before the step, x0 (moved with the
//                collider's translation over the step: the sweep runs in the collider's frame, so
//                a fast collider cannot pass through a particle either), to its position after
//                it, x1, is marched by conservative advancement on the signed distance d
//                (each move is d - thickness long, which cannot cross the thickness shell because
//                d is an exact distance): the first point within the shell is the entry point.
//                A particle that was in contact at x0 (d(x0) within the shell) is not swept: it
//                rests or slides, and x1 is resolved where it is.
//   2. place     the contact point is x1 if it is inside the shell and its nearest surface point
//                is on the side the particle entered through (its normal agrees with the entry
//                point's); otherwise (it passed through, or deeper than the shape's middle) the
//                entry point. A motion that ends outside the shell on the side it came from only
//                grazed it (a particle beside a collider moving along its own surface, a long
//                motion parallel to it in the collider's frame): no contact. The particle moves
//                along the normal to exactly the thickness.
//   3. velocity  relative to the shape's velocity u: the approaching normal part
//                dv_n = -min(0, (v - u).n) is removed (inelastic), and the tangential part's
//                length is reduced by mu dv_n, never below zero (Coulomb; mu is the collider's
//                friction, or the scene's collision.friction when the collider's is negative).
//   4. slide     for a particle in contact at x0, the friction acted through the whole step:
//                its position moves by h/2 times the velocity change friction made (exact for a
//                constant deceleration), so a particle that friction holds does not creep down a
//                slope (at rest it is back where it was, exactly). Implicit Euler holds such a
//                particle in place within its step instead (sticking, below).
// Energy: the stage changes positions and velocities, so it changes the sheet's energy by
// E_after - E_before, booked as ClothState::contact_work. Only the moved particles' kinetic and
// gravitational energy and the springs touching them change; those are summed (in particle and
// gather-slot order, so the sum is the same for any thread count), not the whole sheet.
// Step size: contacts are resolved at step ends, so an impact found late has let the particle's
// neighbours move on while it is pushed back, storing energy in the springs between them. The
// stage therefore limits the next step so that an approaching particle reaches at most a tenth of
// the thickness inside the shell (begin_step()); the integrator's own step control does the rest.
// Resting particles: begin_step() also lists the particles within a collider's shell at the step's
// start (model/surface_contacts.h). Implicit Euler holds them on the surface within its step
// and hands back the normal impulse that took, which step 3 adds to the speed it removed when it
// sizes the friction (Coulomb on the whole normal impulse of the step).
// Limit: with the explicit integrators, a particle pressed onto an obstacle by a load dips into it
// within every step and is put back at the step's end; whatever the integrator dissipates during
// that dip (spring damping, its own numerical damping) the projection books back as positive
// contact work (docs/collisions.md).
// Determinism: particles are resolved in parallel, each writing only its own scratch entries;
// the bookkeeping that follows runs in particle index order.
//
// The stage runs this pass first and self-collision (collision/self_contacts.h) second
// (collision/collision_stage.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "collision/contact_energy.h"
#include "core/vec3.h"
#include "forces/forces.h"
#include "model/cloth_model.h"
#include "model/surface_contacts.h"

namespace clothsim {

// What one application of the collision stage did.
struct ContactCounts {
  std::size_t contacts = 0;  // particles in contact after the stage (moved to the thickness)
  double work = 0.0;         // energy change the stage caused, J (also added to state.contact_work)
};

// Scratch of the obstacle pass, sized for one model on first use; neither call allocates after.
class ObstacleContacts {
 public:
  // Before a step: the latest time the step may end (+infinity without colliders): the earliest
  // time a particle approaching a collider at its current velocity would be kImpactDepth (a
  // tenth) of the thickness inside the shell. Particles within the shell already, and resting
  // and sliding particles (no approach), do not limit it.
  double begin_step(const ClothModel& model, const ClothState& state, int threads);
  // After the step from time `start_time`, where the particles were at `start` [particle_count()]:
  // resolves every free particle against every collider (see the top of the file) and books the
  // energy change in state.contact_work. `terms` are the simulation's force terms, so that the
  // energy booked is the energy the balance measures.
  ContactCounts apply(const ClothModel& model, ClothState& state, std::span<const Vec3> start, double start_time,
                      ForceTerms terms, int threads);
  // The particles begin_step() found resting on a collider, for the integrator to hold there; the
  // integrator writes the impulses, which apply() turns into friction.
  SurfaceContacts& surface_contacts() { return surface_; }
  // Bytes of scratch memory held.
  std::size_t bytes() const;
  // The most bytes() reports on the lattice of `counts` once a collider is in the scene
  // (sim/memory_estimate.h).
  static std::size_t bytes_for(const LatticeCounts& counts) {
    return counts.particles * (2 * sizeof(Vec3) + sizeof(double) + sizeof(std::uint8_t)) +
           ContactEnergy::bytes_for(counts) + SurfaceContacts::bytes_for(counts.particles);
  }

 private:
  void resize(const ClothModel& model);

  std::vector<Vec3> resolved_position_;  // [particles] m, after the pass (valid where moved)
  std::vector<Vec3> resolved_velocity_;  // [particles] m/s, after the pass (valid where moved)
  std::vector<double> arrival_;          // [particles] s from the step's start, see begin_step()
  std::vector<std::uint8_t> moved_;      // [particles] 1: the pass changes this particle
  ContactEnergy energy_;                 // the bookkeeping of what moved
  SurfaceContacts surface_;              // particles resting on a collider at the step's start
};

}  // namespace clothsim
