// The collision stage's obstacle pass: particles against the model's colliders, between
// accepted steps. docs/collisions.md has each step's details, the energy bookkeeping, the step
// limit and the limits measured.
//
// Design: a projection plus a velocity correction on the accepted state, after the step and
// before the events, instead of a contact force inside the derivative. The explicit integrators
// never see a contact, so every one of them (RKF45's error control included) integrates smooth
// stages, and a contact is resolved exactly to the thickness at every step end; implicit Euler
// also holds resting particles on their surface within its step. Rejected: penalty forces, whose
// stiffness would set RKF45's step size everywhere near an obstacle, and which leave particles
// inside by an amount that depends on the load.
//
// For each free particle and each collider, in collider index order, with the collider at the
// step's end time t1:
//   1. sweep     in the collider's frame, the segment x0 -> x1 is marched by conservative
//                advancement on the exact signed distance; the first point within the thickness
//                shell is the entry point (a particle in contact at x0 is not swept);
//   2. place     the contact point is x1 if it is inside the shell on the side the particle
//                entered through, otherwise the entry point; a motion that ends outside on the
//                side it came from only grazed it. The particle moves along the normal to exactly
//                the thickness;
//   3. velocity  relative to the shape's velocity: the approaching normal part is removed
//                (inelastic) and the tangential part reduced by Coulomb friction;
//   4. slide     for a particle in contact at x0, the position moves by the share of the velocity
//                change friction made over the step, so that friction holds a sheet on a slope
//                without creep.
// Energy: the stage's change of the sheet's energy, E_after - E_before, is booked as
// ClothState::contact_work, summed over the moved particles only (in particle and gather-slot
// order). begin_step() limits the next step so that an approaching particle reaches at most a
// tenth of the thickness inside the shell, and lists the particles resting on a collider
// (model/surface_contacts.h) for implicit Euler, whose normal impulses step 3 then uses to size
// the friction.
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
