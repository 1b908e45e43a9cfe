#version 450
#extension GL_GOOGLE_include_directive : require
// The acceleration of stage i (ClothDynamics::evaluate on the CPU): each particle gathers its
// force (gather.glsl: gravity, air drag and its element slots, written by the element passes)
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
layout(std430, binding = 13) writeonly buffer ParticlePower { Real particle_power[]; };  // [stages][2][particles], W

layout(push_constant) uniform Constants { StagePassConstants constants; };

#include "gpu/shaders/anchor_motion.glsl"
#include "gpu/shaders/gather.glsl"

void main() {
  const uint p = invocation_index();
  const uint n = constants.particle_count;
  if (p >= n || control_uint[kActive] == 0u) return;
  const Vec3 v = Vec3(velocity[3 * p], velocity[3 * p + 1], velocity[3 * p + 2]);
  const Vec3 force = gathered_force(p, v);
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
  particle_power[2 * constants.stage * n + p] = -environment[3] * dot(v, v);
  particle_power[(2 * constants.stage + 1) * n + p] = anchor_power;
}
