#version 450
#extension GL_GOOGLE_include_directive : require
// BlockSystem::compute_jacobians (src/integrators/block_system.cpp) on the device: one invocation
// per element (the connectors, then the radial springs) writes its Jacobians' factors at the
// step's start (forces/element_jacobian.inc, the CPU's text), zeros for an element that is broken
// or whose term is off. The compressed connectors' geometric stiffness is clamped, as on the CPU.
#include "gpu/shaders/element_jacobian.glsl"
#include "gpu/shaders/implicit_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Position { Real position[]; };  // [3 particle_count], m
layout(std430, binding = 1) readonly buffer Velocity { Real velocity[]; };  // [3 particle_count], m/s
layout(std430, binding = 2) readonly buffer ConnectorParticles { uint connector_particles[]; };  // [2 connectors]
layout(std430, binding = 3) readonly buffer RestLength { Real connector_rest_length[]; };       // m
layout(std430, binding = 4) readonly buffer ConnectorStiffness { Real connector_stiffness[]; };  // N/m
layout(std430, binding = 5) readonly buffer ConnectorDamping { Real connector_damping[]; };      // N s/m
layout(std430, binding = 6) readonly buffer ConnectorActive { uint connector_active[]; };  // 1: live and its term on
layout(std430, binding = 7) readonly buffer RadialParticles { uint radial_particles[]; };  // [3 radials]: centre, b, c
layout(std430, binding = 8) readonly buffer RestAngle { Real radial_rest_angle[]; };      // rad
layout(std430, binding = 9) readonly buffer RadialStiffness { Real radial_stiffness[]; };  // N m/rad
layout(std430, binding = 10) readonly buffer RadialDamping { Real radial_damping[]; };     // N m s/rad
layout(std430, binding = 11) readonly buffer FadeLength { Real radial_fade_length[]; };   // [2 radials], m
layout(std430, binding = 12) readonly buffer RadialActive { uint radial_active[]; };
layout(std430, binding = 13) writeonly buffer ConnectorFactors { Real connector_factors[]; };  // [connectors][kConnectorFactorReals]
layout(std430, binding = 14) writeonly buffer RadialFactors { Real radial_factors[]; };  // [radials][kRadialFactorReals]

layout(push_constant) uniform Constants { ImplicitPassConstants constants; };

Vec3 particle_position(uint i) { return Vec3(position[3 * i], position[3 * i + 1], position[3 * i + 2]); }
Vec3 particle_velocity(uint i) { return Vec3(velocity[3 * i], velocity[3 * i + 1], velocity[3 * i + 2]); }

void store_connector(uint e, ConnectorLinearization f) {
  const uint base = kConnectorFactorReals * e;
  connector_factors[base] = f.direction.x;
  connector_factors[base + 1] = f.direction.y;
  connector_factors[base + 2] = f.direction.z;
  connector_factors[base + 3] = f.along;
  connector_factors[base + 4] = f.across;
  connector_factors[base + 5] = f.damping;
}

void store_vector(uint index, Vec3 v) {
  radial_factors[index] = v.x;
  radial_factors[index + 1] = v.y;
  radial_factors[index + 2] = v.z;
}

void store_radial(uint r, RadialLinearization f) {
  const uint base = kRadialFactorReals * r;
  store_vector(base, f.gradient_a);
  store_vector(base + 3, f.gradient_b);
  store_vector(base + 6, f.gradient_c);
  radial_factors[base + 9] = f.in_plane_stiffness;
  radial_factors[base + 10] = f.damping;
  store_vector(base + 11, f.transverse_axis);
  radial_factors[base + 14] = f.straight ? Real(1.0) : Real(0.0);
  store_vector(base + 15, f.sum_tilt);
  store_vector(base + 18, f.difference_tilt);
  radial_factors[base + 21] = f.equal_coupling;
  radial_factors[base + 22] = f.opposite_coupling;
}

void main() {
  const uint index = invocation_index();
  const bool damped = constants.damped != 0u;
  if (index < constants.connector_count) {
    const uint e = index;
    ConnectorLinearization f;
    f.direction = Vec3(0.0);
    f.along = Real(0.0);
    f.across = Real(0.0);
    f.damping = Real(0.0);
    if (connector_active[e] != 0u) {
      f = connector_linearization(particle_position(connector_particles[2 * e]),
                                  particle_position(connector_particles[2 * e + 1]), connector_rest_length[e],
                                  connector_stiffness[e], damped ? connector_damping[e] : Real(0.0), true);
    }
    store_connector(e, f);
    return;
  }
  const uint r = index - constants.connector_count;
  if (r >= constants.radial_count) return;
  const uint centre = radial_particles[3 * r];
  const uint b = radial_particles[3 * r + 1];
  const uint c = radial_particles[3 * r + 2];
  // An inactive spring: zero stiffness and damping give zero factors throughout.
  const bool live = radial_active[r] != 0u;
  const RadialLinearization f = radial_linearization(
      particle_position(centre), particle_position(b), particle_position(c), particle_velocity(centre),
      particle_velocity(b), particle_velocity(c), radial_rest_angle[r], live ? radial_stiffness[r] : Real(0.0),
      live && damped ? radial_damping[r] : Real(0.0), radial_fade_length[2 * r], radial_fade_length[2 * r + 1]);
  store_radial(r, f);
}
