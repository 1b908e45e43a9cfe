#version 450
#extension GL_GOOGLE_include_directive : require
// A frame's energies and the Simulation's state checks on the device, so that the host neither
// reads the whole state for them nor sums a large sheet's springs (gpu/state_checks.h; docs/gpu.md,
// "Frames without the host"). Per workgroup of particles: the energies of its particles and of
// the springs each owns (lattice_elements' order: its east and south connectors, its six radial
// springs), as compute_energy sums them on the host (forces/forces.h), and how many of its
// particles fail a check of Simulation::check_state: a non-finite position or velocity, or a live
// connector it owns longer than explosion_stretch times its rest length. The arithmetic is double
// in both precisions (state_checks.glsl).
#include "gpu/shaders/state_checks.glsl"
#include "gpu/shaders/device_step.h"

layout(std430, binding = 6) readonly buffer Params { Stored lattice_params[]; };     // [particles][kLatticeParams]
layout(std430, binding = 7) readonly buffer EventParams { Stored event_params[]; };  // [particles][kEventParams]

layout(push_constant) uniform Constants { StateCheckConstants constants; };

#include "gpu/shaders/lattice_cell.glsl"

Real param(uint at) { return Real(lattice_params[at]); }

// Particle p's terms and those of the springs it owns, in block_checks' order (kCheckKinetic, ...).
Real[kStateCheckReals] particle_checks(uint p) {
  if (p >= constants.particle_count) return no_terms();
  const LatticeCell cell = lattice_cell(p, constants.rows, constants.cols);
  const Vec3 x = state_position(p);
  Real checks[kStateCheckReals] =
      particle_terms(p, Vec3(constants.gravity_x, constants.gravity_y, constants.gravity_z));
  const uint base = p * kLatticeParams;
  Vec3 arm_x[4];
  for (uint d = 0u; d < 4u; ++d) arm_x[d] = cell.has[d] ? state_position(cell.neighbour[d]) : x;
  for (uint d = 0u; d < 2u; ++d) {
    const uint c = base + kConnectorParams + kSpringParams * d;
    if (!cell.has[d] || param(c + kParamActive) == Real(0.0)) continue;
    add_connector_terms(checks, x, arm_x[d], param(c + kParamRest), param(c + kParamStiffness),
                        constants.explosion_stretch);
  }
  for (uint k = 0u; k < uint(kRadialsPerParticle); ++k) {
    const uint r = base + kRadialParams + kSpringParams * k;
    const uint b = uint(kRadialArmB[k]);
    const uint c = uint(kRadialArmC[k]);
    if (!cell.has[b] || !cell.has[c] || param(r + kParamActive) == Real(0.0)) continue;
    const Real fade_b = kRadialFadeFraction * Real(event_params[arm_event_params(b, cell, p) + kEventOriginalLength]);
    const Real fade_c = kRadialFadeFraction * Real(event_params[arm_event_params(c, cell, p) + kEventOriginalLength]);
    const Real energy = checked_radial_energy(x, arm_x[b], arm_x[c], lattice_params[r + kParamRest],
                                              param(r + kParamStiffness), fade_b, fade_c);
    // The four adjacent pairs first, then the two opposite ones (model/lattice_springs.inc).
    checks[k < 4u ? kCheckRadialAdjacent : kCheckRadialOpposite] += energy;
  }
  return checks;
}

void main() { store_workgroup_sums(particle_checks(invocation_index()), workgroup_index()); }
