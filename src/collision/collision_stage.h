// The collision stage: between accepted steps, the sheet out of the obstacles, then out of itself
// (docs/collisions.md).
//
//   begin_step  keeps the positions at the step's start, from which both passes sweep, and
//               returns the time the step may not pass (an impact on an obstacle ahead)
//   apply       after the step: the obstacle pass (collision/obstacle_contacts.h), then the
//               self-collision pass (collision/self_contacts.h)
// An integrator that resolves the obstacles itself (a device integrator, gpu/device_integrator.h)
// leaves the stage the self pass alone: CollisionPasses::self_only; one that runs the self pass too
// (gpu/device_implicit_euler.h) leaves it nothing: CollisionPasses::none.
//
// The self pass has the last word, because it is the one that guarantees something across steps
// (no crossing), which any later move could break. It may push a particle lying on an obstacle
// into it (by about the thickness at most: a layer pressed onto the one below); the next step's
// obstacle pass puts it back out. Rejected: a second obstacle pass after the self pass, which made
// crossings in the built-in `pile` (a fold squeezed between two layers under a rod, pushed back
// through one of them); and holding particles in contact with an obstacle fixed in the self pass,
// which left two layers wrapped under a rod, both held, impossible to separate.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "collision/obstacle_contacts.h"
#include "collision/self_contacts.h"
#include "core/vec3.h"
#include "forces/forces.h"
#include "model/cloth_model.h"

namespace clothsim {

// Which passes the stage runs: both, the self pass alone (the obstacles resolved by the integrator),
// or none (both resolved by the integrator).
enum class CollisionPasses : std::uint8_t { all, self_only, none };

struct CollisionCounts {
  ContactCounts obstacles;
  SelfContactCounts self;
};

class CollisionStage {
 public:
  // Before a step; +infinity when nothing limits it (always, self_only and none).
  double begin_step(const ClothModel& model, const ClothState& state, int threads,
                    CollisionPasses passes = CollisionPasses::all);
  // After the step begun by begin_step(), the passes it was begun for; their energy changes are
  // booked in state.contact_work.
  CollisionCounts apply(const ClothModel& model, ClothState& state, ForceTerms terms, int threads);
  std::size_t bytes() const;
  // The bytes the stage holds on the lattice of `counts` with colliders (`obstacles`) and
  // self-collision, once they have run (sim/memory_estimate.h); none with neither.
  static std::size_t bytes_for(const LatticeCounts& counts, bool obstacles, bool self_collision) {
    if (!obstacles && !self_collision) return 0;
    return counts.particles * sizeof(Vec3) + (obstacles ? ObstacleContacts::bytes_for(counts) : 0) +
           (self_collision ? SelfContacts::bytes_for(counts) : 0);
  }
  // Particles resting on a collider at the step's start, for an integrator to hold on its surface
  // (model/surface_contacts.h); refreshed by begin_step().
  SurfaceContacts& surface_contacts() { return obstacles_.surface_contacts(); }

 private:
  bool active_ = false;  // begin_step() found colliders or self-collision
  CollisionPasses passes_ = CollisionPasses::all;
  double start_time_ = 0.0;
  std::vector<Vec3> start_position_;  // [particles] m, at the step's start
  ObstacleContacts obstacles_;
  SelfContacts self_;
};

}  // namespace clothsim
