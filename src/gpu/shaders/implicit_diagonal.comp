#version 450
#extension GL_GOOGLE_include_directive : require
// Implicit Euler's block Jacobi preconditioner on the device, and its resting contacts, one
// invocation per particle (BlockSystem::assemble's `preconditioner`, ImplicitEuler's
// hold_on_surfaces and release_held_particles on the CPU, implicit_euler_contacts.cpp):
//   kDiagonalHold     the diagonal block D of the particle's row (its elements' k_s K + d_s C in the
//                     gather table's order, its mass and drag) and, where the host's surface
//                     contacts say it rests on an obstacle and its predicted motion goes into the
//                     surface, the hold: along the normal (sliding), or in all three directions
//                     (stuck, where friction can stop it within the step), with the held part of dv
//                     set to move with the surface. Stores the preconditioner's block: the inverse
//                     of D, of S D S completed by n n^T, or zero (anchored, or held altogether).
//   kDiagonalRelease  after the solve, from the surface impulse A dv - b (implicit_gather): a
//                     surface that would have to pull lets go (the solve runs again), and a stuck
//                     particle held by more than Coulomb's friction slides from the next step on.
#include "gpu/shaders/element_jacobian.glsl"
#include "gpu/shaders/implicit_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer GatherOffset { uint gather_offset[]; };
layout(std430, binding = 1) readonly buffer GatherSlot { uint gather_slot[]; };
layout(std430, binding = 2) readonly buffer ConnectorFactors { Real connector_factors[]; };
layout(std430, binding = 3) readonly buffer RadialFactors { Real radial_factors[]; };
layout(std430, binding = 4) readonly buffer Mass { Real particle_mass[]; };
layout(std430, binding = 5) readonly buffer Environment { Real environment[]; };
layout(std430, binding = 6) readonly buffer ParticleAnchor { int particle_anchor[]; };
layout(std430, binding = 7) readonly buffer SolveReal { Real solve_real[]; };
layout(std430, binding = 8) writeonly buffer Jacobi { Real jacobi[]; };  // [particle_count][9], column by column
layout(std430, binding = 9) readonly buffer SurfaceContacts { Real surface_contacts[]; };  // [particles][kContactReals]
layout(std430, binding = 10) buffer Hold { uint hold[]; };        // [particle_count], kHold*
layout(std430, binding = 11) buffer Slipped { uint slipped[]; };  // [particle_count], 1: held stuck by more than friction last step
layout(std430, binding = 12) readonly buffer Force { Real force[]; };  // [3 particle_count], f0, N
layout(std430, binding = 13) readonly buffer Velocity { Real velocity[]; };  // [3 particle_count], m/s
layout(std430, binding = 14) buffer Solution { Real solution[]; };  // [3 particle_count], dv
layout(std430, binding = 15) readonly buffer Impulse { Real impulse[]; };  // [3 particle_count], N s
layout(std430, binding = 16) buffer SolveUint { uint solve_uint[]; };

layout(push_constant) uniform Constants { ImplicitPassConstants constants; };

#include "gpu/shaders/implicit_factors.glsl"
#include "gpu/shaders/held_directions.glsl"

// The arrays vector3() reads.
const uint kForce = 0u, kVelocity = 1u, kSolution = 2u, kImpulse = 3u;

Vec3 vector3(uint p, uint array) {
  const uint i = 3 * p;
  if (array == kForce) return Vec3(force[i], force[i + 1], force[i + 2]);
  if (array == kVelocity) return Vec3(velocity[i], velocity[i + 1], velocity[i + 2]);
  if (array == kSolution) return Vec3(solution[i], solution[i + 1], solution[i + 2]);
  return Vec3(impulse[i], impulse[i + 1], impulse[i + 2]);
}

Mat3 diagonal_block(uint p) {
  const Real stiffness_scale = solve_real[kStiffnessScale];
  const Real damping_scale = solve_real[kDampingScale];
  Mat3 block = Mat3(0.0);
  for (uint k = gather_offset[p]; k < gather_offset[p + 1]; ++k) {
    const uint slot = gather_slot[k];
    if (slot < constants.radial_slot_base) {
      block += connector_diagonal(load_connector(slot / 2u), stiffness_scale, damping_scale);
    } else {
      const uint local = slot - constants.radial_slot_base;
      block += radial_diagonal(load_radial(local / 3u), local % 3u, stiffness_scale, damping_scale);
    }
  }
  return block + (particle_mass[p] + damping_scale * environment[3]) * Mat3(1.0);
}

// BlockSystem::set_hold's block: D^-1; (S D S + n n^T)^-1 along the normal; zero held altogether.
void store_preconditioner(uint p, Mat3 d, uint how) {
  Mat3 inverse_block = Mat3(0.0);
  if (how == kHoldNone) {
    inverse_block = inverse(d);
  } else if (how == kHoldNormal) {
    const Vec3 n = contact_normal(p);
    const Vec3 dn = d * n;
    inverse_block = inverse(d - outerProduct(n, dn) - outerProduct(dn, n) + (dot(n, dn) + Real(1.0)) * outerProduct(n, n));
  }
  for (uint column = 0u; column < 3u; ++column) {
    for (uint row = 0u; row < 3u; ++row) jacobi[9 * p + 3 * column + row] = inverse_block[column][row];
  }
}

// The hold of a free particle at the step's start (ImplicitEuler::hold_on_surfaces), and the held
// part of its dv.
uint decide_hold(uint p) {
  const uint c = kContactReals * p;
  if (solve_uint[kHolding] == 0u || surface_contacts[c + kContactResting] == Real(0.0)) return kHoldNone;
  const Vec3 n = contact_normal(p);
  const Vec3 surface_velocity = Vec3(surface_contacts[c + 3], surface_contacts[c + 4], surface_contacts[c + 5]);
  const Real friction = surface_contacts[c + 6];
  const Real h = solve_real[kImplicitStep];
  const Real mass = particle_mass[p];
  const Vec3 f = vector3(p, kForce);
  const Vec3 v = vector3(p, kVelocity);
  const Vec3 relative = v - surface_velocity;
  // Held when the explicit prediction of the step's end velocity moves it into the surface.
  const Vec3 predicted = relative + (h / mass) * f;
  if (dot(predicted, n) >= Real(0.0)) return kHoldNone;
  // Stuck when friction can stop its slide and hold it against the tangential force within the
  // step: |m v_t / h + f_t| <= mu |f_n|; a particle the last step found needing more slides.
  const Real pressing = -dot(f, n) - dot(relative, n) * mass / h;
  const Vec3 slide = mass / h * relative + f;
  const Vec3 tangential = slide - dot(slide, n) * n;
  const bool stuck = slipped[p] == 0u && length(tangential) <= friction * max(Real(0.0), pressing);
  slipped[p] = 0u;
  // The held part of dv is known: the step ends moving with the surface, along the normal or altogether.
  const Vec3 to_surface = surface_velocity - v;
  const Vec3 dv = vector3(p, kSolution);
  const Vec3 held_dv = stuck ? to_surface : dv - dot(dv, n) * n + dot(to_surface, n) * n;
  for (uint k = 0u; k < 3u; ++k) solution[3 * p + k] = held_dv[k];
  return stuck ? kHoldAll : kHoldNormal;
}

void main() {
  const uint p = invocation_index();
  if (p >= constants.particle_count) return;
  if (particle_anchor[p] >= 0) {
    hold[p] = kHoldNone;
    store_preconditioner(p, Mat3(0.0), kHoldAll);  // outside the system: zero
    return;
  }
  if (constants.phase == kDiagonalHold) {
    const uint how = decide_hold(p);
    hold[p] = how;
    store_preconditioner(p, diagonal_block(p), how);
    return;
  }
  // kDiagonalRelease: a surface cannot pull, and friction cannot exceed mu times the normal impulse.
  const uint how = hold[p];
  if (how == kHoldNone) return;
  const Vec3 n = contact_normal(p);
  const Vec3 surface_impulse = vector3(p, kImpulse);
  const Real pressing = dot(n, surface_impulse);
  if (pressing < Real(0.0)) {
    hold[p] = kHoldNone;
    store_preconditioner(p, diagonal_block(p), kHoldNone);
    solve_uint[kReleased] = 1u;
  } else if (how == kHoldAll &&
             length(surface_impulse - pressing * n) > surface_contacts[kContactReals * p + 6] * pressing) {
    slipped[p] = 1u;
  }
}
