#version 450
#extension GL_GOOGLE_include_directive : require
// The element forces of a lattice sheet by particle, without element lists or force slots: the
// device's form of the CPU's structured kernel (forces/lattice_kernel.h). Each particle evaluates
// the springs it owns, in build_lattice's order: its east and south connectors and the six radial
// springs centred at it (arms 0 east, 1 south, 2 west, 3 north; pairs (E,S), (S,W), (W,N), (N,E),
// (E,W), (S,N)), with element_math.inc's formulas, and writes the sum of their forces on itself,
// their forces on each of its four neighbours (which stage_acceleration gathers), and their
// damping power. Parameters come per particle (lattice_params), so torn, plastic and creased
// sheets take this path too: a missing, broken or switched-off spring has active 0. The radial
// springs fade as an arm vanishes, with the arm connector's original length from event_params. A
// uniform sheet's particles all read one interior particle's parameters (params_particle).
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/device_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Position { Real position[]; };    // stage state [3 particles], m
layout(std430, binding = 1) readonly buffer Velocity { Real velocity[]; };    // m/s (float32: offsets)
layout(std430, binding = 2) readonly buffer Params { Real lattice_params[]; };  // [particles][kLatticeParams]
layout(std430, binding = 3) writeonly buffer Forces { Real lattice_forces[]; };  // [particles][kLatticeForces]
layout(std430, binding = 4) buffer ParticlePower { Real particle_power[]; };  // [3][particles], W (device_step.h)
layout(std430, binding = 5) readonly buffer ControlUint { uint control_uint[]; };
layout(std430, binding = 6) readonly buffer EventParams { Real event_params[]; };  // [particles][kEventParams]
layout(std430, binding = 7) readonly buffer OriginPosition { Real origin_position[]; };  // the step's start, m
layout(std430, binding = 8) readonly buffer OriginVelocity { Real origin_velocity[]; };  // m/s
layout(std430, binding = 9) readonly buffer Rows { Real rows[]; };  // the method's Nystrom rows

layout(push_constant) uniform Constants { LatticePassConstants constants; };

#include "gpu/shaders/lattice_cell.glsl"
#include "gpu/shaders/stage_offsets.glsl"

void main() {
  const uint p = invocation_index();
  const uint n = constants.particle_count;
  if (p >= n || control_uint[kActive] == 0u) return;
  const LatticeCell cell = lattice_cell(p, constants.rows, constants.cols);
  const bool has[4] = cell.has;
  const uint neighbour[4] = cell.neighbour;
  // Near p: in float32, relative to p (stage_offsets.glsl).
  const Vec3 x = stage_position_near(p, p);
  const Vec3 v = stage_velocity_near(p, p);
  const bool one_source = constants.params_particle != kOwnParams;
  const uint source = one_source ? constants.params_particle : p;
  Vec3 arm_x[4];
  Vec3 arm_v[4];
  Real fade_length[4];
  for (uint d = 0u; d < 4u; ++d) {
    arm_x[d] = has[d] ? stage_position_near(neighbour[d], p) : x;
    arm_v[d] = has[d] ? stage_velocity_near(neighbour[d], p) : v;
    // On a uniform sheet the west and north arms are as long as the east and south ones.
    const uint arm = one_source ? source * kEventParams + kEventsPerConnector * (d % 2u) : arm_event_params(d, cell, p);
    fade_length[d] = has[d] ? kRadialFadeFraction * event_params[arm + kEventOriginalLength] : Real(0.0);
  }
  const uint base = source * kLatticeParams;
  const Real damped = constants.damped != 0u ? Real(1.0) : Real(0.0);
  Vec3 own = Vec3(0.0);
  Vec3 to[4] = Vec3[4](Vec3(0.0), Vec3(0.0), Vec3(0.0), Vec3(0.0));
  Real power = Real(0.0);
  // East (d 0) and south (d 1) connectors.
  for (uint d = 0u; d < 2u; ++d) {
    const uint c = base + kConnectorParams + kSpringParams * d;
    if (!has[d] || lattice_params[c + kParamActive] == Real(0.0)) continue;
    const ConnectorForce f =
        connector_force(x, arm_x[d], v, arm_v[d], lattice_params[c + kParamRest], lattice_params[c + kParamStiffness],
                        damped * lattice_params[c + kParamDamping]);
    own += f.force_on_a;
    to[d] -= f.force_on_a;
    power += f.damping_power;
  }
  // The six radial springs.
  for (uint k = 0u; k < uint(kRadialsPerParticle); ++k) {
    const uint r = base + kRadialParams + kSpringParams * k;
    const uint b = uint(kRadialArmB[k]);
    const uint c = uint(kRadialArmC[k]);
    if (!has[b] || !has[c] || lattice_params[r + kParamActive] == Real(0.0)) continue;
    const RadialForce f =
        radial_force(x, arm_x[b], arm_x[c], v, arm_v[b], arm_v[c], lattice_params[r + kParamRest],
                     lattice_params[r + kParamStiffness], damped * lattice_params[r + kParamDamping],
                     fade_length[b], fade_length[c]);
    own -= f.force_on_b + f.force_on_c;
    to[b] += f.force_on_b;
    to[c] += f.force_on_c;
    power += f.damping_power;
  }
  const uint slot = p * kLatticeForces;
  lattice_forces[slot] = own.x;
  lattice_forces[slot + 1u] = own.y;
  lattice_forces[slot + 2u] = own.z;
  for (uint d = 0u; d < 4u; ++d) {
    lattice_forces[slot + 3u + 3u * d] = to[d].x;
    lattice_forces[slot + 4u + 3u * d] = to[d].y;
    lattice_forces[slot + 5u + 3u * d] = to[d].z;
  }
  // Weighed by the solution row, summed over the stages (device_step.h).
  const Real weight = rows[solution_weight_slot(constants.stages, constants.stage)];
  particle_power[2u * n + p] = (constants.stage == 0u ? Real(0.0) : particle_power[2u * n + p]) + weight * power;
}
