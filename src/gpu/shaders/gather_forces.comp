#version 450
#extension GL_GOOGLE_include_directive : require
// gather_forces (src/forces/forces.cpp) on the device: one invocation per particle adds gravity
// and air drag to its element slots, summed in the gather table's order (model/gather_table.h),
// the same operations in the same order as the CPU: no atomics, and a result that does not
// depend on how the invocations are scheduled.
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/element_pass.h"

layout(local_size_x_id = 0) in;  // the workgroup size, a specialization constant

layout(std430, binding = 0) readonly buffer Velocity { Real velocity[]; };        // [3 particle_count], m/s
layout(std430, binding = 1) readonly buffer Mass { Real particle_mass[]; };       // [particle_count], kg
layout(std430, binding = 2) readonly buffer Environment { Real environment[]; };  // gravity x, y, z (m/s^2; 0 when off), drag (kg/s; 0 when off)
layout(std430, binding = 3) readonly buffer GatherOffset { uint gather_offset[]; };  // [particle_count + 1]
layout(std430, binding = 4) readonly buffer GatherSlot { uint gather_slot[]; };      // [force_slot_count]
layout(std430, binding = 5) readonly buffer SlotForce { Real slot_force[]; };        // [3 force_slot_count], N
layout(std430, binding = 6) writeonly buffer Force { Real force[]; };                // [3 particle_count], N

layout(push_constant) uniform Constants { GatherConstants constants; };

void main() {
  const uint p = gl_GlobalInvocationID.x;
  if (p >= constants.particle_count) return;
  const Vec3 gravity = Vec3(environment[0], environment[1], environment[2]);
  const Real drag = environment[3];
  const Vec3 v = Vec3(velocity[3 * p], velocity[3 * p + 1], velocity[3 * p + 2]);
  Vec3 sum = particle_mass[p] * gravity - drag * v;
  for (uint k = gather_offset[p]; k < gather_offset[p + 1]; ++k) {
    const uint slot = gather_slot[k];
    sum += Vec3(slot_force[3 * slot], slot_force[3 * slot + 1], slot_force[3 * slot + 2]);
  }
  force[3 * p] = sum.x;
  force[3 * p + 1] = sum.y;
  force[3 * p + 2] = sum.z;
}
