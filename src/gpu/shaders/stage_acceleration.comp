#version 450
#extension GL_GOOGLE_include_directive : require
// The acceleration of stage i (stage_acceleration.glsl): each particle gathers its force
// (gather.glsl: gravity, air drag and its element slots, written by the element passes; or on the
// lattice path, lattice_elements' forces of its own springs and of its four neighbours') and
// writes K_i and its drag and anchor powers.
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/device_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer StageVelocity { Real velocity[]; };       // [3 particles], m/s
layout(std430, binding = 1) readonly buffer Mass { Real particle_mass[]; };           // kg
layout(std430, binding = 2) readonly buffer InverseMass { Real inverse_mass[]; };     // 1/kg; 0 anchored
layout(std430, binding = 3) readonly buffer Environment { Real environment[]; };      // gravity (3), drag
layout(std430, binding = 4) readonly buffer GatherOffset { uint gather_offset[]; };   // [particles + 1]
layout(std430, binding = 5) readonly buffer GatherSlot { uint gather_slot[]; };
layout(std430, binding = 6) readonly buffer SlotForce { Real slot_force[]; };         // [3 slots], N
layout(std430, binding = 7) readonly buffer Rows { Real rows[]; };
layout(std430, binding = 8) readonly buffer ControlReal { Real control_real[]; };
layout(std430, binding = 9) readonly buffer ControlUint { uint control_uint[]; };
layout(std430, binding = 10) readonly buffer ParticleAnchor { int particle_anchor[]; };
layout(std430, binding = 11) readonly buffer AnchorPaths { Real anchor_paths[]; };
layout(std430, binding = 12) writeonly buffer Acceleration { Real acceleration[]; };  // [stages][3 particles]
layout(std430, binding = 13) buffer ParticlePower { Real particle_power[]; };  // [3][particles], W (device_step.h)
layout(std430, binding = 14) readonly buffer LatticeForces { Real lattice_forces[]; };  // the lattice path's
layout(std430, binding = 15) readonly buffer OriginVelocity { Real origin_velocity[]; };  // the step's start, m/s

#define CLOTHSIM_STAGE_VELOCITY_ONLY
#include "gpu/shaders/stage_offsets.glsl"

layout(push_constant) uniform Constants { StagePassConstants constants; };

#include "gpu/shaders/stage_acceleration.glsl"
#include "gpu/shaders/gather.glsl"
#include "gpu/shaders/lattice_cell.glsl"

// The lattice path's force on p: lattice_elements' sums, its own and its neighbours' shares of it
// (the neighbour east of p sends what it puts on its west one: direction d's slot is 3 + 3 d).
Vec3 lattice_force(uint p, Vec3 v) {
  const LatticeCell cell = lattice_cell(p, constants.particle_count / constants.lattice_cols, constants.lattice_cols);
  const uint own = p * kLatticeForces;
  Vec3 from[4];
  for (uint d = 0u; d < 4u; ++d) {
    const uint q = cell.neighbour[d] * kLatticeForces + 3u + 3u * ((d + 2u) % 4u);
    from[d] = cell.has[d] ? Vec3(lattice_forces[q], lattice_forces[q + 1u], lattice_forces[q + 2u]) : Vec3(0.0);
  }
  const Vec3 own_force = Vec3(lattice_forces[own], lattice_forces[own + 1u], lattice_forces[own + 2u]);
  return lattice_force_on(p, v, own_force, cell.has, from);
}

void main() {
  const uint p = invocation_index();
  if (p >= constants.particle_count || control_uint[kActive] == 0u) return;
  const Vec3 v = stage_velocity(p);
  store_stage_acceleration(p, v, constants.lattice_cols == 0u ? gathered_force(p, v) : lattice_force(p, v));
}
