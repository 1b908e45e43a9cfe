#version 450
#extension GL_GOOGLE_include_directive : require
// A frame's energies and the Simulation's state checks on the device, so that the host neither
// reads the whole state for them nor sums a large sheet's springs (gpu/state_checks.h; docs/gpu.md,
// "Frames without the host"). Per workgroup of particles: the energies of its particles and of
// the springs each owns (lattice_elements' order: its east and south connectors, its six radial
// springs), as compute_energy sums them on the host (forces/forces.h), and how many of its
// particles fail a check of Simulation::check_state: a non-finite position or velocity, or a live
// connector it owns longer than explosion_stretch times its rest length.
//
// The arithmetic is double in both variants: the float32 state is read as its two floats a
// coordinate (split_state.glsl) and added in double, so that the sums over a million particles
// keep the host's accuracy (a float sum of the gravitational energies, each a few hundred J,
// would lose whole joules). So the pass needs shaderFloat64 on either precision.
#if CLOTHSIM_FLOAT64
#define Stored double
const bool kSplit = false;
#else
#define Stored float
const bool kSplit = true;  // the state as high + low parts
#endif
#undef CLOTHSIM_FLOAT64
#define CLOTHSIM_FLOAT64 1
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/device_step.h"
#include "gpu/shaders/state_checks.h"

const uint kWorkgroupSize = kStateChecksWorkgroup;
layout(local_size_x = kWorkgroupSize) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Position { Stored position[]; };  // [3 particles], m
layout(std430, binding = 1) readonly buffer Velocity { Stored velocity[]; };  // m/s
layout(std430, binding = 2) readonly buffer PositionLow { Stored position_low[]; };  // float32's low parts
layout(std430, binding = 3) readonly buffer VelocityLow { Stored velocity_low[]; };
layout(std430, binding = 4) readonly buffer Mass { Stored particle_mass[]; };        // kg
layout(std430, binding = 5) readonly buffer Params { Stored lattice_params[]; };     // [particles][kLatticeParams]
layout(std430, binding = 6) readonly buffer EventParams { Stored event_params[]; };  // [particles][kEventParams]
layout(std430, binding = 7) writeonly buffer BlockChecks { double block_checks[]; };  // [blocks][kStateCheckReals]

layout(push_constant) uniform Constants { StateCheckConstants constants; };

#include "gpu/shaders/lattice_cell.glsl"

Vec3 state_position(uint q) {
  Vec3 x = Vec3(position[3 * q], position[3 * q + 1], position[3 * q + 2]);
  if (kSplit) x += Vec3(position_low[3 * q], position_low[3 * q + 1], position_low[3 * q + 2]);
  return x;
}
Vec3 state_velocity(uint q) {
  Vec3 v = Vec3(velocity[3 * q], velocity[3 * q + 1], velocity[3 * q + 2]);
  if (kSplit) v += Vec3(velocity_low[3 * q], velocity_low[3 * q + 1], velocity_low[3 * q + 2]);
  return v;
}
bool finite(Vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }
Real param(uint at) { return Real(lattice_params[at]); }

// Particle p's terms, in block_checks' order.
struct ParticleChecks {
  Real kinetic;
  Real gravitational;
  Real connector;
  Real radial_adjacent;
  Real radial_opposite;
  Real failures;
};

ParticleChecks particle_checks(uint p) {
  const LatticeCell cell = lattice_cell(p, constants.rows, constants.cols);
  const Vec3 x = state_position(p);
  const Vec3 v = state_velocity(p);
  const Real mass = Real(particle_mass[p]);
  const Vec3 gravity = Vec3(constants.gravity_x, constants.gravity_y, constants.gravity_z);
  ParticleChecks checks = ParticleChecks(Real(0.5) * mass * dot(v, v), -mass * dot(gravity, x), Real(0.0), Real(0.0),
                                         Real(0.0), finite(x) && finite(v) ? Real(0.0) : Real(1.0));
  const uint base = p * kLatticeParams;
  Vec3 arm_x[4];
  for (uint d = 0u; d < 4u; ++d) arm_x[d] = cell.has[d] ? state_position(cell.neighbour[d]) : x;
  for (uint d = 0u; d < 2u; ++d) {
    const uint c = base + kConnectorParams + kSpringParams * d;
    if (!cell.has[d] || param(c + kParamActive) == Real(0.0)) continue;
    const Real rest = param(c + kParamRest);
    checks.connector += connector_energy(x, arm_x[d], rest, param(c + kParamStiffness));
    if (norm(arm_x[d] - x) / rest > constants.explosion_stretch) checks.failures = Real(1.0);
  }
  for (uint k = 0u; k < uint(kRadialsPerParticle); ++k) {
    const uint r = base + kRadialParams + kSpringParams * k;
    const uint b = uint(kRadialArmB[k]);
    const uint c = uint(kRadialArmC[k]);
    if (!cell.has[b] || !cell.has[c] || param(r + kParamActive) == Real(0.0)) continue;
    const Real fade_b = kRadialFadeFraction * Real(event_params[arm_event_params(b, cell, p) + kEventOriginalLength]);
    const Real fade_c = kRadialFadeFraction * Real(event_params[arm_event_params(c, cell, p) + kEventOriginalLength]);
    const Real energy =
        radial_energy(x, arm_x[b], arm_x[c], param(r + kParamRest), param(r + kParamStiffness), fade_b, fade_c);
    // The four adjacent pairs first, then the two opposite ones (model/lattice_springs.inc).
    if (k < 4u) {
      checks.radial_adjacent += energy;
    } else {
      checks.radial_opposite += energy;
    }
  }
  return checks;
}

#include "gpu/shaders/workgroup_sums.glsl"

void main() {
  const uint p = invocation_index();
  ParticleChecks checks = ParticleChecks(Real(0.0), Real(0.0), Real(0.0), Real(0.0), Real(0.0), Real(0.0));
  if (p < constants.particle_count) checks = particle_checks(p);
  const uint block = workgroup_index();
  Real first[3] = Real[3](checks.kinetic, checks.gravitational, checks.connector);
  sum_over_workgroup(first);
  if (gl_LocalInvocationID.x == 0u) {
    for (uint k = 0u; k < 3u; ++k) block_checks[kStateCheckReals * block + k] = workgroup_sum[k][0];
  }
  Real second[3] = Real[3](checks.radial_adjacent, checks.radial_opposite, checks.failures);
  sum_over_workgroup(second);
  if (gl_LocalInvocationID.x == 0u) {
    for (uint k = 0u; k < 3u; ++k) block_checks[kStateCheckReals * block + 3u + k] = workgroup_sum[k][0];
  }
}
