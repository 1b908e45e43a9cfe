#version 450
#extension GL_GOOGLE_include_directive : require
// Tearing and permanent stretching on the lattice path, after an accepted step
// (events/spring_events.h, laws 1 and 2, on the accepted state): each particle takes its east
// and south connectors. A live connector past its break strain breaks (active 0, the time noted,
// its elastic energy released as fracture work; lattice_events_radial then breaks the radial
// springs that use it); otherwise one past its yield strain yields by the return mapping (the
// elastic energy's change as plastic work). The laws are the CPU's, events/spring_laws.inc. Each
// particle writes only its own connectors: no two invocations touch one spring.
#include "gpu/shaders/element_math.glsl"
#include "events/spring_laws.inc"
#include "gpu/shaders/device_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Position { Real position[]; };  // the accepted state, m
layout(std430, binding = 1) buffer Params { Real lattice_params[]; };       // [particles][kLatticeParams]
layout(std430, binding = 2) buffer EventParams { Real event_params[]; };    // [particles][kEventParams]
layout(std430, binding = 3) writeonly buffer EventEnergy { Real event_energy[]; };  // [particles][2]: fracture, plastic, J
layout(std430, binding = 4) writeonly buffer EventFlags { uint event_flags[]; };    // [particles]: bit d, connector d broke now
layout(std430, binding = 5) readonly buffer ControlReal { Real control_real[]; };
layout(std430, binding = 6) buffer ControlUint { uint control_uint[]; };

layout(push_constant) uniform Constants { EventPassConstants constants; };

#include "gpu/shaders/lattice_cell.glsl"

Vec3 load_position(uint i) { return Vec3(position[3 * i], position[3 * i + 1], position[3 * i + 2]); }

void main() {
  const uint p = invocation_index();
  if (p >= constants.particle_count || control_uint[kAccepted] == 0u) return;
  const LatticeCell cell = lattice_cell(p, constants.rows, constants.cols);
  const Vec3 x = load_position(p);
  Real fracture = Real(0.0);
  Real plastic = Real(0.0);
  uint broke = 0u;
  for (uint d = 0u; d < 2u; ++d) {
    const uint c = p * kLatticeParams + kConnectorParams + kSpringParams * d;
    const uint e = p * kEventParams + kEventsPerConnector * d;
    if (!cell.has[d] || lattice_params[c + kParamActive] == Real(0.0)) continue;
    const Vec3 xb = load_position(cell.neighbour[d]);
    const Real length = norm(xb - x);
    const Real rest = lattice_params[c + kParamRest];
    const Real stiffness = lattice_params[c + kParamStiffness];
    if ((constants.laws & kLawTearing) != 0u &&
        connector_breaks(length, event_params[e + kEventOriginalLength], event_params[e + kEventBreakStrain])) {
      fracture -= connector_energy(x, xb, rest, stiffness);
      lattice_params[c + kParamActive] = Real(0.0);
      event_params[e + kEventBreakTime] = control_real[kElapsed];
      broke |= 1u << d;
      atomicAdd(control_uint[kBreaks], 1u);
      continue;
    }
    if ((constants.laws & kLawPlasticity) == 0u) continue;
    const Real hardening = control_real[kHardening];
    const ReturnMapping mapping = return_mapping(length, rest, event_params[e + kEventYieldStrain], hardening);
    if (!mapping.yields) continue;
    plastic += connector_energy(x, xb, mapping.rest_length, stiffness) - connector_energy(x, xb, rest, stiffness);
    lattice_params[c + kParamRest] = mapping.rest_length;
    if (hardening != Real(0.0)) event_params[e + kEventYieldStrain] = mapping.yield_strain;
    atomicAdd(control_uint[kYields], 1u);
  }
  event_energy[2u * p] = fracture;
  event_energy[2u * p + 1u] = plastic;
  event_flags[p] = broke;
}
