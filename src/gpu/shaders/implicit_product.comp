#version 450
#extension GL_GOOGLE_include_directive : require
// The element part of a product with implicit Euler's matrix, matrix-free from the element factors
// (implicit_factors.glsl): one invocation per element (the connectors, then the radial springs)
// writes, into each of its force slots (the CPU's slots, gpu/device_forces.h), its row of
// k_s K + d_s C times `direction`; implicit_gather adds each particle's slots in the gather
// table's order, as the CPU assembles a row, with the mass and the drag. The operator: K alone
// (kProductStiffness: the right-hand side's K z) or the system's h C + h^2 K (kProductSystem).
#include "gpu/shaders/element_jacobian.glsl"
#include "gpu/shaders/implicit_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Direction { Real direction[]; };  // [3 particle_count]
layout(std430, binding = 1) readonly buffer ConnectorParticles { uint connector_particles[]; };
layout(std430, binding = 2) readonly buffer RadialParticles { uint radial_particles[]; };
layout(std430, binding = 3) readonly buffer ConnectorFactors { Real connector_factors[]; };
layout(std430, binding = 4) readonly buffer RadialFactors { Real radial_factors[]; };
layout(std430, binding = 5) readonly buffer SolveReal { Real solve_real[]; };
layout(std430, binding = 6) readonly buffer SolveUint { uint solve_uint[]; };
layout(std430, binding = 7) writeonly buffer SlotForce { Real slot_force[]; };  // [3 force slots]

layout(push_constant) uniform Constants { ImplicitPassConstants constants; };

#include "gpu/shaders/implicit_factors.glsl"

Vec3 vector_of(uint i) { return Vec3(direction[3 * i], direction[3 * i + 1], direction[3 * i + 2]); }
void store_slot(uint slot, Vec3 v) {
  slot_force[3 * slot] = v.x;
  slot_force[3 * slot + 1] = v.y;
  slot_force[3 * slot + 2] = v.z;
}

void main() {
  if (constants.iteration != 0u && solve_uint[kSolveDone] != 0u) return;
  const uint index = invocation_index();
  const bool system = constants.phase == kProductSystem;
  const Real stiffness_scale = system ? solve_real[kStiffnessScale] : Real(1.0);
  const Real damping_scale = system ? solve_real[kDampingScale] : Real(0.0);
  if (index < constants.connector_count) {
    const uint e = index;
    const Vec3 w = vector_of(connector_particles[2 * e]) - vector_of(connector_particles[2 * e + 1]);
    const Vec3 on_a = connector_product(load_connector(e), stiffness_scale, damping_scale, w);
    store_slot(2 * e, on_a);
    store_slot(2 * e + 1, -on_a);
    return;
  }
  const uint r = index - constants.connector_count;
  if (r >= constants.radial_count) return;
  const RadialLinearization f = load_radial(r);
  const Vec3 v0 = vector_of(radial_particles[3 * r]);
  const Vec3 v1 = vector_of(radial_particles[3 * r + 1]);
  const Vec3 v2 = vector_of(radial_particles[3 * r + 2]);
  const Real rate = dot(f.gradient_a, v0) + dot(f.gradient_b, v1) + dot(f.gradient_c, v2);
  const Real along = (stiffness_scale * f.in_plane_stiffness + damping_scale * f.damping) * rate;
  const Vec3 sum = f.sum_tilt.x * v0 + f.sum_tilt.y * v1 + f.sum_tilt.z * v2;
  const Vec3 difference = f.difference_tilt.x * v0 + f.difference_tilt.y * v1 + f.difference_tilt.z * v2;
  const uint slot = constants.radial_slot_base + 3 * r;
  for (uint i = 0u; i < 3u; ++i) {
    const Vec3 transverse =
        f.equal_coupling * f.sum_tilt[i] * sum + f.opposite_coupling * f.difference_tilt[i] * difference;
    store_slot(slot + i, along * radial_gradient(f, i) + stiffness_scale * transverse_projection(f, transverse));
  }
}
