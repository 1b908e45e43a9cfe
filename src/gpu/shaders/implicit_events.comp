#version 450
#extension GL_GOOGLE_include_directive : require
// Tearing, permanent stretching and creasing after implicit Euler's step on the device
// (events/spring_events.h, on the state after the step and its obstacle pass; the lattice path's
// lattice_events_*.comp do the same for the explicit methods), on DeviceForces' element arrays:
//   kEventsConnectorsPhase  per connector: a live one past its break strain breaks (active 0, the
//                           time noted, its elastic energy released as fracture work); otherwise one
//                           past its yield strain yields by the return mapping (the elastic
//                           energy's change as plastic work, and the yield strain hardened)
//   kEventsRadialsPhase     per radial spring: a live one whose arm connector broke now breaks with
//                           it (fracture work); otherwise one further than its yield angle from its
//                           rest angle creases (plastic work)
// The laws are the CPU's text, events/spring_laws.inc; each invocation writes only its own spring.
// Each workgroup writes its fracture and plastic work at first_block + its index in block_sums,
// which implicit_reduce (kReduceEvents) adds in order; the counts are atomic increments of integers.
#include "gpu/shaders/element_math.glsl"
#include "events/spring_laws.inc"
#include "gpu/shaders/device_step.h"
#include "gpu/shaders/implicit_step.h"

const uint kWorkgroupSize = kImplicitReduceWorkgroup;
layout(local_size_x = kWorkgroupSize) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Position { Real position[]; };  // m
layout(std430, binding = 1) readonly buffer ConnectorParticles { uint connector_particles[]; };  // [2 connectors]
layout(std430, binding = 2) buffer ConnectorRest { Real connector_rest_length[]; };              // m
layout(std430, binding = 3) readonly buffer ConnectorStiffness { Real connector_stiffness[]; };  // N/m
layout(std430, binding = 4) buffer ConnectorActive { uint connector_active[]; };  // not 0: live (its term on)
layout(std430, binding = 5) readonly buffer RadialParticles { uint radial_particles[]; };  // [3 radials]
layout(std430, binding = 6) buffer RadialRest { Real radial_rest_angle[]; };               // rad
layout(std430, binding = 7) readonly buffer RadialStiffness { Real radial_stiffness[]; };  // N m/rad
layout(std430, binding = 8) readonly buffer RadialFade { Real radial_fade_length[]; };     // [2 radials], m
layout(std430, binding = 9) buffer RadialActive { uint radial_active[]; };                 // 0: absent or broken
layout(std430, binding = 10) buffer ConnectorEvents { Real connector_events[]; };  // [connectors][kEventsPerConnector]
layout(std430, binding = 11) readonly buffer RadialArms { uint radial_arms[]; };   // [2 radials]: connectors
layout(std430, binding = 12) readonly buffer RadialYield { Real radial_yield_angle[]; };  // rad, +inf: elastic
layout(std430, binding = 13) buffer ConnectorBroke { uint connector_broke[]; };  // 1: broke after this step
layout(std430, binding = 14) writeonly buffer BlockSums { Real block_sums[]; };   // [blocks][3]
layout(std430, binding = 15) readonly buffer SolveReal { Real solve_real[]; };
layout(std430, binding = 16) buffer SolveUint { uint solve_uint[]; };

layout(push_constant) uniform Constants { EventElementConstants constants; };

Vec3 load_position(uint i) { return Vec3(position[3 * i], position[3 * i + 1], position[3 * i + 2]); }

// Connector e's laws; its fracture and plastic work.
Real[2] connector_laws(uint e) {
  Real work[2] = Real[2](Real(0.0), Real(0.0));
  connector_broke[e] = 0u;
  if (connector_active[e] == 0u) return work;
  const Vec3 xa = load_position(connector_particles[2 * e]);
  const Vec3 xb = load_position(connector_particles[2 * e + 1]);
  const Real length = norm(xb - xa);
  const Real rest = connector_rest_length[e];
  const Real stiffness = connector_stiffness[e];
  const uint t = kEventsPerConnector * e;
  if ((constants.laws & kLawTearing) != 0u &&
      connector_breaks(length, connector_events[t + kEventOriginalLength], connector_events[t + kEventBreakStrain])) {
    work[0] = -connector_energy(xa, xb, rest, stiffness);
    connector_active[e] = 0u;
    connector_events[t + kEventBreakTime] = solve_real[kEventTime];
    connector_broke[e] = 1u;
    atomicAdd(solve_uint[kEventBreaks], 1u);
    return work;
  }
  if ((constants.laws & kLawPlasticity) == 0u) return work;
  const Real hardening = solve_real[kEventHardening];
  const ReturnMapping mapping = return_mapping(length, rest, connector_events[t + kEventYieldStrain], hardening);
  if (!mapping.yields) return work;
  work[1] = connector_energy(xa, xb, mapping.rest_length, stiffness) - connector_energy(xa, xb, rest, stiffness);
  connector_rest_length[e] = mapping.rest_length;
  if (hardening != Real(0.0)) connector_events[t + kEventYieldStrain] = mapping.yield_strain;
  atomicAdd(solve_uint[kEventYields], 1u);
  return work;
}

// Radial spring r's laws; its fracture and plastic work.
Real[2] radial_laws(uint r) {
  Real work[2] = Real[2](Real(0.0), Real(0.0));
  if (radial_active[r] == 0u) return work;
  const Vec3 x = load_position(radial_particles[3 * r]);
  const Vec3 xb = load_position(radial_particles[3 * r + 1]);
  const Vec3 xc = load_position(radial_particles[3 * r + 2]);
  const Real rest = radial_rest_angle[r];
  const Real stiffness = radial_stiffness[r];
  const Real fade_b = radial_fade_length[2 * r];
  const Real fade_c = radial_fade_length[2 * r + 1];
  if (connector_broke[radial_arms[2 * r]] != 0u || connector_broke[radial_arms[2 * r + 1]] != 0u) {
    work[0] = -radial_energy(x, xb, xc, rest, stiffness, fade_b, fade_c);
    radial_active[r] = 0u;
    return work;
  }
  if ((constants.laws & kLawCreasing) == 0u) return work;
  const Real new_rest = creased_rest_angle(radial_angle(x, xb, xc), rest, radial_yield_angle[r]);
  if (new_rest == rest) return work;
  work[1] = radial_energy(x, xb, xc, new_rest, stiffness, fade_b, fade_c) -
            radial_energy(x, xb, xc, rest, stiffness, fade_b, fade_c);
  radial_rest_angle[r] = new_rest;
  atomicAdd(solve_uint[kEventCreases], 1u);
  return work;
}

#include "gpu/shaders/workgroup_sums.glsl"

void main() {
  const uint i = invocation_index();
  Real work[2] = Real[2](Real(0.0), Real(0.0));
  if (i < constants.count) work = constants.phase == kEventsConnectorsPhase ? connector_laws(i) : radial_laws(i);
  Real sums[3] = Real[3](work[0], work[1], Real(0.0));
  sum_over_workgroup(sums);
  if (gl_LocalInvocationID.x == 0u) {
    const uint block = constants.first_block + workgroup_index();
    for (uint k = 0u; k < 3u; ++k) block_sums[3 * block + k] = workgroup_sum[k][0];
  }
}
