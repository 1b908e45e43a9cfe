#version 450
#extension GL_GOOGLE_include_directive : require
// The acceleration of stage i (ClothDynamics::evaluate on the CPU): each particle gathers its
// force (gather.glsl: gravity, air drag and its element slots, written by the element passes; or
// on the lattice path, lattice_elements' forces of its own springs and of its four neighbours')
// and divides it by its mass; an anchored particle takes its path's acceleration instead, and the
// power its anchor puts in, v . (m a - f). Writes K_i and the particle's drag and anchor powers
// for the stage, which rk_accept weights into the step's work.
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

#include "gpu/shaders/anchor_motion.glsl"
#include "gpu/shaders/gather.glsl"

// The lattice path's force on p: gravity and drag, its own springs' force on it, and each
// neighbour's springs' force on it (the neighbour east of p sends what it puts on its west one).
Vec3 lattice_force(uint p, Vec3 v) {
  const uint cols = constants.lattice_cols;
  const uint n = constants.particle_count;
  const uint col = p % cols;
  Vec3 sum = particle_mass[p] * Vec3(environment[0], environment[1], environment[2]) - environment[3] * v;
  const uint own = p * kLatticeForces;
  sum += Vec3(lattice_forces[own], lattice_forces[own + 1u], lattice_forces[own + 2u]);
  // Direction d's slot of `from`: 3 + 3 d.
  if (col + 1u < cols) {  // east neighbour, its slot west (2)
    const uint q = (p + 1u) * kLatticeForces + 9u;
    sum += Vec3(lattice_forces[q], lattice_forces[q + 1u], lattice_forces[q + 2u]);
  }
  if (p + cols < n) {  // south neighbour, its slot north (3)
    const uint q = (p + cols) * kLatticeForces + 12u;
    sum += Vec3(lattice_forces[q], lattice_forces[q + 1u], lattice_forces[q + 2u]);
  }
  if (col > 0u) {  // west neighbour, its slot east (0)
    const uint q = (p - 1u) * kLatticeForces + 3u;
    sum += Vec3(lattice_forces[q], lattice_forces[q + 1u], lattice_forces[q + 2u]);
  }
  if (p >= cols) {  // north neighbour, its slot south (1)
    const uint q = (p - cols) * kLatticeForces + 6u;
    sum += Vec3(lattice_forces[q], lattice_forces[q + 1u], lattice_forces[q + 2u]);
  }
  return sum;
}

void main() {
  const uint p = invocation_index();
  const uint n = constants.particle_count;
  if (p >= n || control_uint[kActive] == 0u) return;
  const Vec3 v = stage_velocity(p);
  const Vec3 force = constants.lattice_cols == 0u ? gathered_force(p, v) : lattice_force(p, v);
  Vec3 a = inverse_mass[p] * force;
  Real anchor_power = Real(0.0);
  const int anchor = particle_anchor[p];
  if (anchor >= 0) {
    const Real tau = control_real[kElapsed] + rows[constants.stage * kRowReals] * control_real[kStep];
    a = anchor_motion(uint(anchor), tau).acceleration;
    anchor_power = dot(v, particle_mass[p] * a - force);
  }
  const uint base = 3 * (constants.stage * n + p);
  acceleration[base] = a.x;
  acceleration[base + 1] = a.y;
  acceleration[base + 2] = a.z;
  // The powers weighed by the solution row, summed over the stages (device_step.h).
  const Real weight = rows[solution_weight_slot(constants.stages, constants.stage)];
  const bool first = constants.stage == 0u;
  particle_power[p] = (first ? Real(0.0) : particle_power[p]) + weight * (-environment[3] * dot(v, v));
  particle_power[n + p] = (first ? Real(0.0) : particle_power[n + p]) + weight * anchor_power;
}
