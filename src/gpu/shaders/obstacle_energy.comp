#version 450
#extension GL_GOOGLE_include_directive : require
// What the obstacle pass did to an accepted step, per workgroup of particles, for rk_control's
// phase 1 (ObstacleContacts::apply's bookkeeping and ObstacleContacts::begin_step on the CPU):
//   the energy change, the sheet's energy after the pass minus before it: each particle the pass
//     moved, its kinetic and gravitational energy; each spring a particle owns (lattice_elements'
//     order) that touches a moved particle, its elastic energy;
//   the particles it moved;
//   the earliest time, from the step's end, at which a free particle outside every thickness shell
//     and approaching a collider at its velocity would be impact_depth() inside the shell: the
//     next step may not pass it.
// Before the pass a particle was where `contact_before` says if it moved, where the trial state
// says otherwise. The CPU sums the energy of the changed particles and springs before and after
// and subtracts; here each particle's and spring's change is formed first, then summed.
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/device_step.h"

const uint kWorkgroupSize = kReduceWorkgroup;
layout(local_size_x = kWorkgroupSize) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer ControlReal { Real control_real[]; };
layout(std430, binding = 1) readonly buffer ControlUint { uint control_uint[]; };
layout(std430, binding = 2) readonly buffer TrialPosition { Real trial_position[]; };  // after the pass, m
layout(std430, binding = 3) readonly buffer TrialVelocity { Real trial_velocity[]; };  // m/s
layout(std430, binding = 4) readonly buffer ContactBefore { Real contact_before[]; };  // [6 particles]
layout(std430, binding = 5) readonly buffer Moved { uint moved[]; };
layout(std430, binding = 6) readonly buffer ParticleAnchor { int particle_anchor[]; };
layout(std430, binding = 7) readonly buffer Colliders { Real colliders[]; };
layout(std430, binding = 8) readonly buffer Mass { Real particle_mass[]; };          // kg
layout(std430, binding = 9) readonly buffer Environment { Real environment[]; };     // gravity (3), drag
layout(std430, binding = 10) readonly buffer Params { Real lattice_params[]; };      // [particles][kLatticeParams]
layout(std430, binding = 11) readonly buffer EventParams { Real event_params[]; };   // [particles][kEventParams]
layout(std430, binding = 12) writeonly buffer BlockObstacles { Real block_obstacles[]; };  // [blocks][3]
layout(std430, binding = 13) readonly buffer MeshReals { Real mesh_reals[]; };  // device_step.h, kMeshHeaderUints
layout(std430, binding = 14) readonly buffer MeshUints { uint mesh_uints[]; };

layout(push_constant) uniform Constants { ObstaclePassConstants constants; };

#include "gpu/shaders/obstacle_surface.glsl"
#include "gpu/shaders/lattice_cell.glsl"

const Real kNoArrival = Real(CLOTHSIM_NO_ARRIVAL);

Vec3 after_position(uint q) { return Vec3(trial_position[3 * q], trial_position[3 * q + 1], trial_position[3 * q + 2]); }
Vec3 after_velocity(uint q) { return Vec3(trial_velocity[3 * q], trial_velocity[3 * q + 1], trial_velocity[3 * q + 2]); }
Vec3 before_position(uint q) {
  if (moved[q] == 0u) return after_position(q);
  return Vec3(contact_before[6 * q], contact_before[6 * q + 1], contact_before[6 * q + 2]);
}
Vec3 before_velocity(uint q) {
  if (moved[q] == 0u) return after_velocity(q);
  return Vec3(contact_before[6 * q + 3], contact_before[6 * q + 4], contact_before[6 * q + 5]);
}

// The change of the energy of particle p and of the springs it owns.
Real energy_change(uint p) {
  const LatticeCell cell = lattice_cell(p, constants.rows, constants.cols);
  Real change = Real(0.0);
  if (moved[p] != 0u) {
    const Vec3 gravity = Vec3(environment[0], environment[1], environment[2]);
    const Vec3 v1 = after_velocity(p);
    const Vec3 v0 = before_velocity(p);
    change += Real(0.5) * particle_mass[p] * (dot(v1, v1) - dot(v0, v0)) -
              particle_mass[p] * dot(gravity, after_position(p) - before_position(p));
  }
  const uint base = p * kLatticeParams;
  for (uint d = 0u; d < 2u; ++d) {
    const uint c = base + kConnectorParams + kSpringParams * d;
    if (!cell.has[d] || lattice_params[c + kParamActive] == Real(0.0)) continue;
    const uint q = cell.neighbour[d];
    if (moved[p] == 0u && moved[q] == 0u) continue;
    const Real rest = lattice_params[c + kParamRest];
    const Real stiffness = lattice_params[c + kParamStiffness];
    change += connector_energy(after_position(p), after_position(q), rest, stiffness) -
              connector_energy(before_position(p), before_position(q), rest, stiffness);
  }
  for (uint k = 0u; k < uint(kRadialsPerParticle); ++k) {
    const uint r = base + kRadialParams + kSpringParams * k;
    const uint b = uint(kRadialArmB[k]);
    const uint c = uint(kRadialArmC[k]);
    if (!cell.has[b] || !cell.has[c] || lattice_params[r + kParamActive] == Real(0.0)) continue;
    const uint qb = cell.neighbour[b];
    const uint qc = cell.neighbour[c];
    if (moved[p] == 0u && moved[qb] == 0u && moved[qc] == 0u) continue;
    const Real rest = lattice_params[r + kParamRest];
    const Real stiffness = lattice_params[r + kParamStiffness];
    const Real fade_b = kRadialFadeFraction * event_params[arm_event_params(b, cell, p) + kEventOriginalLength];
    const Real fade_c = kRadialFadeFraction * event_params[arm_event_params(c, cell, p) + kEventOriginalLength];
    change += radial_energy(after_position(p), after_position(qb), after_position(qc), rest, stiffness, fade_b,
                            fade_c) -
              radial_energy(before_position(p), before_position(qb), before_position(qc), rest, stiffness, fade_b,
                            fade_c);
  }
  return change;
}

// The earliest arrival of free particle p at a collider, s from the step's end (kNoArrival: none).
Real earliest_arrival(uint p) {
  const Real thickness = control_real[kThickness];
  const Real depth = impact_depth(thickness);
  const Vec3 x = after_position(p);
  const Vec3 v = after_velocity(p);
  Real arrival = kNoArrival;
  for (uint c = 0u; c < constants.colliders; ++c) {
    const SurfaceDistance surface = obstacle_surface(obstacle_at(c, control_real[kElapsed]), x);
    if (within_shell(surface, thickness)) continue;
    const Real t = arrival_time(surface, v, thickness, depth);
    if (t >= Real(0.0)) arrival = min(arrival, t);
  }
  return arrival;
}

#include "gpu/shaders/workgroup_sums.glsl"

void main() {
  if (control_uint[kAccepted] == 0u) return;  // the same for the whole dispatch
  const uint p = invocation_index();
  // The energy change, the particles moved, the earliest arrival.
  Real partial[3] = Real[3](Real(0.0), Real(0.0), kNoArrival);
  if (p < constants.particle_count) {
    partial[0] = energy_change(p);
    partial[1] = Real(moved[p]);
    if (particle_anchor[p] < 0) partial[2] = earliest_arrival(p);
  }
  reduce_over_workgroup(partial, true);
  if (gl_LocalInvocationID.x == 0u) {
    const uint block = workgroup_index();
    for (uint k = 0u; k < kObstacleBlockReals; ++k) {
      block_obstacles[kObstacleBlockReals * block + k] = workgroup_sum[k][0];
    }
  }
}
