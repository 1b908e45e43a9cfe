#version 450
#extension GL_GOOGLE_include_directive : require
// The radial springs' side of the events on the lattice path, after lattice_events_connectors
// (events/spring_events.h): each particle takes its six radial springs. One whose arm connector
// broke in this step breaks with it (its elastic energy released as fracture work); a live one
// whose angle is further than its yield angle from its rest angle creases by the CPU's law,
// events/spring_laws.inc (the elastic energy's change as plastic work). Each workgroup then sums
// its particles' fracture and plastic work for rk_control's phase 2.
#include "gpu/shaders/element_math.glsl"
#include "events/spring_laws.inc"
#include "gpu/shaders/device_step.h"

const uint kWorkgroupSize = kReduceWorkgroup;
layout(local_size_x = kWorkgroupSize) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Position { Real position[]; };  // the accepted state, m
layout(std430, binding = 1) buffer Params { Real lattice_params[]; };       // [particles][kLatticeParams]
layout(std430, binding = 2) readonly buffer EventParams { Real event_params[]; };
layout(std430, binding = 3) readonly buffer EventEnergy { Real event_energy[]; };  // [particles][2]
layout(std430, binding = 4) readonly buffer EventFlags { uint event_flags[]; };
layout(std430, binding = 5) buffer ControlUint { uint control_uint[]; };
layout(std430, binding = 6) writeonly buffer BlockEvents { Real block_events[]; };  // [blocks][2], J

layout(push_constant) uniform Constants { EventPassConstants constants; };

#include "gpu/shaders/lattice_cell.glsl"

Vec3 load_position(uint i) { return Vec3(position[3 * i], position[3 * i + 1], position[3 * i + 2]); }

// Whether the connector of arm d of particle p (east and south its own, west and north its
// neighbours') broke in this step.
bool arm_broke(uint d, LatticeCell cell, uint p) {
  if (d < 2u) return (event_flags[p] & (1u << d)) != 0u;
  return (event_flags[cell.neighbour[d]] & (1u << (d - 2u))) != 0u;
}

#include "gpu/shaders/workgroup_sums.glsl"

void main() {
  if (control_uint[kAccepted] == 0u) return;  // the same for the whole dispatch
  const uint p = invocation_index();
  Real fracture = Real(0.0);
  Real plastic = Real(0.0);
  if (p < constants.particle_count) {
    const LatticeCell cell = lattice_cell(p, constants.rows, constants.cols);
    const Vec3 x = load_position(p);
    fracture = event_energy[2u * p];
    plastic = event_energy[2u * p + 1u];
    for (uint k = 0u; k < uint(kRadialsPerParticle); ++k) {
      const uint r = p * kLatticeParams + kRadialParams + kSpringParams * k;
      const uint b = uint(kRadialArmB[k]);
      const uint c = uint(kRadialArmC[k]);
      if (!cell.has[b] || !cell.has[c] || lattice_params[r + kParamActive] == Real(0.0)) continue;
      const Vec3 xb = load_position(cell.neighbour[b]);
      const Vec3 xc = load_position(cell.neighbour[c]);
      const Real rest = lattice_params[r + kParamRest];
      const Real stiffness = lattice_params[r + kParamStiffness];
      // The fade of vanishing arms (element_math.inc), from the arm connectors' original lengths.
      const Real fade_b = kRadialFadeFraction * event_params[arm_event_params(b, cell, p) + kEventOriginalLength];
      const Real fade_c = kRadialFadeFraction * event_params[arm_event_params(c, cell, p) + kEventOriginalLength];
      if (arm_broke(b, cell, p) || arm_broke(c, cell, p)) {
        fracture -= radial_energy(x, xb, xc, rest, stiffness, fade_b, fade_c);
        lattice_params[r + kParamActive] = Real(0.0);
        continue;
      }
      const Real yield_angle = event_params[p * kEventParams + kRadialYieldAngles + k];
      if ((constants.laws & kLawCreasing) == 0u) continue;
      const Real new_rest = creased_rest_angle(radial_angle(x, xb, xc), rest, yield_angle);
      if (new_rest == rest) continue;
      plastic += radial_energy(x, xb, xc, new_rest, stiffness, fade_b, fade_c) -
                 radial_energy(x, xb, xc, rest, stiffness, fade_b, fade_c);
      lattice_params[r + kParamRest] = new_rest;
      atomicAdd(control_uint[kCreases], 1u);
    }
  }
  Real works[3] = Real[3](fracture, plastic, Real(0.0));
  sum_over_workgroup(works);
  const uint group = workgroup_index();
  if (gl_LocalInvocationID.x == 0u && group < constants.blocks) {
    block_events[2u * group] = workgroup_sum[0][0];
    block_events[2u * group + 1u] = workgroup_sum[1][0];
  }
}
