// Particles resting on an obstacle at a step's start, which an integrator may hold on the surface
// during the step instead of letting them move into it (docs/collisions.md).
//
// The collision stage's obstacle pass fills it before each step (collision/obstacle_contacts.h);
// implicit Euler reads it (integrators/implicit_euler.h): it removes the normal direction of the
// particles whose predicted motion goes into the surface from its linear solve (Baraff and
// Witkin's filter), and writes back the normal impulse the surface had to exert, which the
// obstacle pass then turns into Coulomb friction. The explicit integrators ignore it: their steps
// are small enough that the projection between steps suffices (docs/collisions.md, measured).
//
// Per-particle arrays, so that filling and reading them in parallel is deterministic.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/vec3.h"

namespace clothsim {

struct SurfaceContacts {
  // The first collider (in scene order) whose thickness shell holds the particle at the step's
  // start; kNone where none does, or for anchored particles.
  static constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<std::uint32_t> collider;  // [particles]
  std::vector<Vec3> normal;             // [particles] unit, out of the surface (valid where collider != kNone)
  std::vector<Vec3> velocity;           // [particles] m/s, the surface's velocity at the step's start
  std::vector<double> friction;         // [particles] the Coulomb coefficient between them
  // Written by an integrator that holds particles on their surface: the normal impulse the surface
  // exerted on the particle over the step (N s, >= 0); zero where the particle was not held.
  std::vector<double> impulse;  // [particles]
  bool any = false;             // some particle has a collider

  void resize(std::size_t particles) {
    collider.assign(particles, kNone);
    normal.assign(particles, Vec3{});
    velocity.assign(particles, Vec3{});
    friction.assign(particles, 0.0);
    impulse.assign(particles, 0.0);
    any = false;
  }
  // The bytes bytes() reports after resize(particles).
  static constexpr std::size_t bytes_for(std::size_t particles) {
    return particles * (sizeof(std::uint32_t) + 2 * sizeof(Vec3) + 2 * sizeof(double));
  }
  std::size_t bytes() const {
    return collider.capacity() * sizeof(std::uint32_t) + (normal.capacity() + velocity.capacity()) * sizeof(Vec3) +
           (friction.capacity() + impulse.capacity()) * sizeof(double);
  }
};

}  // namespace clothsim
