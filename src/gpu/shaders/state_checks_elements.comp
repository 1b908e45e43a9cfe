#version 450
#extension GL_GOOGLE_include_directive : require
// The state checks of state_checks.comp on the general path (a sheet that is not a lattice, and
// implicit Euler's device step, which read DeviceForces' element arrays): one dispatch over the
// particles (kinetic and gravitational energy, a non-finite state), one over the connectors
// (elastic energy, a live connector longer than explosion_stretch times its rest length), one over
// the radial springs (elastic energy, by kind: DeviceForces' radial_active holds it). Each
// workgroup writes its sums at its place in block_checks; the host adds them all in order.
#include "gpu/shaders/state_checks.glsl"
#include "gpu/shaders/element_pass.h"

layout(std430, binding = 6) readonly buffer ConnectorParticles { uint connector_particles[]; };  // [2 connectors]
layout(std430, binding = 7) readonly buffer ConnectorRest { Stored connector_rest_length[]; };    // m
layout(std430, binding = 8) readonly buffer ConnectorStiffness { Stored connector_stiffness[]; };  // N/m
layout(std430, binding = 9) readonly buffer ConnectorActive { uint connector_active[]; };  // not 0: live, term on
layout(std430, binding = 10) readonly buffer RadialParticles { uint radial_particles[]; };  // [3 radials]: centre, b, c
layout(std430, binding = 11) readonly buffer RadialRest { Stored radial_rest_angle[]; };     // rad
layout(std430, binding = 12) readonly buffer RadialStiffness { Stored radial_stiffness[]; };  // N m/rad
layout(std430, binding = 13) readonly buffer RadialFade { Stored radial_fade_length[]; };  // [2 radials], m
layout(std430, binding = 14) readonly buffer RadialActive { uint radial_active[]; };  // 0, or kRadialActive*

layout(push_constant) uniform Constants { ElementCheckConstants constants; };

// Item i's terms in block_checks' order (kCheckKinetic, ...).
Real[kStateCheckReals] item_terms(uint i) {
  Real terms[kStateCheckReals] = no_terms();
  if (i >= constants.count) return terms;
  if (constants.phase == kCheckParticlesPhase) {
    terms = particle_terms(i, Vec3(constants.gravity_x, constants.gravity_y, constants.gravity_z));
  } else if (constants.phase == kCheckConnectorsPhase) {
    if (connector_active[i] == 0u) return terms;
    add_connector_terms(terms, state_position(connector_particles[2 * i]),
                        state_position(connector_particles[2 * i + 1]), Real(connector_rest_length[i]),
                        Real(connector_stiffness[i]), constants.explosion_stretch);
  } else {
    if (radial_active[i] == 0u) return terms;
    const Real energy = checked_radial_energy(
        state_position(radial_particles[3 * i]), state_position(radial_particles[3 * i + 1]),
        state_position(radial_particles[3 * i + 2]), radial_rest_angle[i], Real(radial_stiffness[i]),
        Real(radial_fade_length[2 * i]), Real(radial_fade_length[2 * i + 1]));
    terms[radial_active[i] == kRadialActiveAdjacent ? kCheckRadialAdjacent : kCheckRadialOpposite] = energy;
  }
  return terms;
}

void main() { store_workgroup_sums(item_terms(invocation_index()), constants.first_block + workgroup_index()); }
