#version 450
#extension GL_GOOGLE_include_directive : require
// What the obstacle pass (and the self pass after it, where it runs on the device) did to implicit
// Euler's step on the device, on DeviceForces' element arrays (gpu/device_implicit_obstacles.cpp;
// obstacle_energy.comp is the lattice path's), and what the next step needs from the state it left.
// One dispatch per phase, each workgroup writing its kObstacleBlockReals at first_block + its index
// in block_obstacles, which implicit_reduce (kReduceObstacles) adds in order:
//   kObstacleParticlesPhase   per particle: a moved particle's change of kinetic and gravitational
//                             energy, the work of the impulse its surface exerted while it was held
//                             (ImplicitEuler::book_surface_impulses: impulse . v at the step's end),
//                             1 if the obstacle pass moved it, and, for a free particle, the surface it now rests on
//                             (its row of surface_contacts, for the next step's holds) or the
//                             earliest time at which it would be impact_depth() inside a collider's
//                             shell (ObstacleContacts::begin_step on the CPU); any resting particle
//                             sets solve_uint[kResting], any particle whose state changed
//                             solve_uint[kStateChanged]
//   kObstacleConnectorsPhase  a connector with a moved particle: its energy after less before
//   kObstacleRadialsPhase     a radial spring likewise
// `start`: at an advance's start, where nothing has moved (the flags are zero), the particles'
// phase alone, for the surface contacts and the first step's limit. The CPU sums the energy of
// the changed particles and springs before the pass and after it and subtracts; here each change
// is formed first, then summed, as obstacle_energy does.
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/device_step.h"
#include "gpu/shaders/implicit_step.h"

const uint kWorkgroupSize = kReduceWorkgroup;
layout(local_size_x = kWorkgroupSize) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer ControlReal { Real control_real[]; };  // kElapsed, kThickness
layout(std430, binding = 1) readonly buffer Position { Real position[]; };       // after the pass, m
layout(std430, binding = 2) readonly buffer Velocity { Real velocity[]; };       // m/s
layout(std430, binding = 3) readonly buffer ContactBefore { Real contact_before[]; };  // [6 particles]
layout(std430, binding = 4) readonly buffer Moved { uint moved[]; };
layout(std430, binding = 5) readonly buffer ParticleAnchor { int particle_anchor[]; };
layout(std430, binding = 6) readonly buffer Colliders { Real colliders[]; };
layout(std430, binding = 7) readonly buffer Mass { Real particle_mass[]; };       // kg
layout(std430, binding = 8) readonly buffer Environment { Real environment[]; };  // gravity (3), drag
layout(std430, binding = 9) readonly buffer ConnectorParticles { uint connector_particles[]; };  // [2 connectors]
layout(std430, binding = 10) readonly buffer ConnectorRest { Real connector_rest_length[]; };    // m
layout(std430, binding = 11) readonly buffer ConnectorStiffness { Real connector_stiffness[]; };  // N/m
layout(std430, binding = 12) readonly buffer ConnectorActive { uint connector_active[]; };  // not 0: live, term on
layout(std430, binding = 13) readonly buffer RadialParticles { uint radial_particles[]; };  // [3 radials]
layout(std430, binding = 14) readonly buffer RadialRest { Real radial_rest_angle[]; };     // rad
layout(std430, binding = 15) readonly buffer RadialStiffness { Real radial_stiffness[]; };  // N m/rad
layout(std430, binding = 16) readonly buffer RadialFade { Real radial_fade_length[]; };    // [2 radials], m
layout(std430, binding = 17) readonly buffer RadialActive { uint radial_active[]; };       // 0: absent or off
layout(std430, binding = 18) writeonly buffer BlockObstacles { Real block_obstacles[]; };  // [blocks][3]
layout(std430, binding = 19) readonly buffer MeshReals { Real mesh_reals[]; };  // device_step.h, kMeshHeaderUints
layout(std430, binding = 20) readonly buffer MeshUints { uint mesh_uints[]; };
layout(std430, binding = 21) writeonly buffer SurfaceContacts { Real surface_contacts[]; };  // [particles][8]
layout(std430, binding = 22) readonly buffer Impulse { Real impulse[]; };  // [3 particles], N s
layout(std430, binding = 23) readonly buffer Hold { uint hold[]; };        // [particles], kHold*
layout(std430, binding = 24) buffer SolveUint { uint solve_uint[]; };

layout(push_constant) uniform Constants { ObstacleElementConstants constants; };

#include "gpu/shaders/obstacle_surface.glsl"

const Real kNoArrival = Real(CLOTHSIM_NO_ARRIVAL);

Vec3 after_position(uint q) { return Vec3(position[3 * q], position[3 * q + 1], position[3 * q + 2]); }
Vec3 after_velocity(uint q) { return Vec3(velocity[3 * q], velocity[3 * q + 1], velocity[3 * q + 2]); }
bool was_moved(uint q) { return constants.start == 0u && moved[q] != 0u; }
Vec3 before_position(uint q) {
  if (!was_moved(q)) return after_position(q);
  return Vec3(contact_before[6 * q], contact_before[6 * q + 1], contact_before[6 * q + 2]);
}
Vec3 before_velocity(uint q) {
  if (!was_moved(q)) return after_velocity(q);
  return Vec3(contact_before[6 * q + 3], contact_before[6 * q + 4], contact_before[6 * q + 5]);
}

// Free particle p against the colliders at the pass's time: its row of surface_contacts (the first
// collider whose shell holds it), and its earliest arrival at another, s (kNoArrival: none).
Real rest_or_arrival(uint p) {
  const Real thickness = control_real[kThickness];
  const Real depth = impact_depth(thickness);
  const Vec3 x = after_position(p);
  const Vec3 v = after_velocity(p);
  Real arrival = kNoArrival;
  Real row[kContactReals] = Real[kContactReals](Real(0.0), Real(0.0), Real(0.0), Real(0.0), Real(0.0), Real(0.0),
                                                Real(0.0), Real(0.0));
  for (uint c = 0u; c < constants.colliders; ++c) {
    const SurfaceDistance surface = obstacle_surface(obstacle_at(c, control_real[kElapsed]), x);
    if (within_shell(surface, thickness)) {
      if (row[kContactResting] == Real(0.0)) {
        row = Real[kContactReals](surface.normal.x, surface.normal.y, surface.normal.z, surface.velocity.x,
                                  surface.velocity.y, surface.velocity.z,
                                  colliders[c * kColliderReals + kColliderFriction], Real(c + 1u));
      }
      continue;
    }
    const Real t = arrival_time(surface, v, thickness, depth);
    if (t >= Real(0.0)) arrival = min(arrival, t);
  }
  for (uint k = 0u; k < kContactReals; ++k) surface_contacts[kContactReals * p + k] = row[k];
  if (row[kContactResting] != Real(0.0)) solve_uint[kResting] = 1u;  // the same word from every writer
  return arrival;
}

// Item i's energy change, 1 if it is a particle the pass moved, and its earliest arrival.
Real[3] item_values(uint i) {
  Real values[3] = Real[3](Real(0.0), Real(0.0), kNoArrival);
  if (i >= constants.count) return values;
  if (constants.phase == kObstacleParticlesPhase) {
    if (particle_anchor[i] >= 0) {
      for (uint k = 0u; k < kContactReals; ++k) surface_contacts[kContactReals * i + k] = Real(0.0);
      return values;
    }
    if (was_moved(i)) {
      const Vec3 gravity = Vec3(environment[0], environment[1], environment[2]);
      const Vec3 v1 = after_velocity(i);
      const Vec3 v0 = before_velocity(i);
      values[0] = Real(0.5) * particle_mass[i] * (dot(v1, v1) - dot(v0, v0)) -
                  particle_mass[i] * dot(gravity, after_position(i) - before_position(i));
      // The particles the obstacle pass moved; the self pass marks those it moved first 2
      // (shaders/self_step.h, kMovedBySelf), whose energy change is booked here too.
      values[1] = moved[i] == 1u ? Real(1.0) : Real(0.0);
      // A particle the pass touched may be left as it was (one resting at the thickness): the
      // step's end forces then still hold, as the CPU finds by comparing the states.
      if (after_position(i) != before_position(i) || v1 != v0) solve_uint[kStateChanged] = 1u;
    }
    if (constants.start == 0u && hold[i] != kHoldNone) {
      values[0] += dot(Vec3(impulse[3 * i], impulse[3 * i + 1], impulse[3 * i + 2]), before_velocity(i));
    }
    values[2] = rest_or_arrival(i);
  } else if (constants.phase == kObstacleConnectorsPhase) {
    const uint a = connector_particles[2 * i];
    const uint b = connector_particles[2 * i + 1];
    if (connector_active[i] == 0u || (!was_moved(a) && !was_moved(b))) return values;
    const Real rest = connector_rest_length[i];
    const Real stiffness = connector_stiffness[i];
    values[0] = connector_energy(after_position(a), after_position(b), rest, stiffness) -
                connector_energy(before_position(a), before_position(b), rest, stiffness);
  } else {
    const uint a = radial_particles[3 * i];
    const uint b = radial_particles[3 * i + 1];
    const uint c = radial_particles[3 * i + 2];
    if (radial_active[i] == 0u || (!was_moved(a) && !was_moved(b) && !was_moved(c))) return values;
    const Real rest = radial_rest_angle[i];
    const Real stiffness = radial_stiffness[i];
    const Real fade_b = radial_fade_length[2 * i];
    const Real fade_c = radial_fade_length[2 * i + 1];
    values[0] = radial_energy(after_position(a), after_position(b), after_position(c), rest, stiffness, fade_b,
                              fade_c) -
                radial_energy(before_position(a), before_position(b), before_position(c), rest, stiffness, fade_b,
                              fade_c);
  }
  return values;
}

#include "gpu/shaders/workgroup_sums.glsl"

void main() {
  Real values[3] = item_values(invocation_index());
  reduce_over_workgroup(values, true);
  if (gl_LocalInvocationID.x == 0u) {
    const uint block = constants.first_block + workgroup_index();
    for (uint k = 0u; k < kObstacleBlockReals; ++k) {
      block_obstacles[kObstacleBlockReals * block + k] = workgroup_sum[k][0];
    }
  }
}
