#version 450
#extension GL_GOOGLE_include_directive : require
// gather_forces (src/forces/forces.cpp) on the device: one invocation per particle adds gravity
// and air drag to its element slots, summed in the gather table's order (model/gather_table.h),
// the same operations in the same order as the CPU: no atomics, and a result that does not
// depend on how the invocations are scheduled.
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/element_pass.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Velocity { Real velocity[]; };        // [3 particle_count], m/s
layout(std430, binding = 1) readonly buffer Mass { Real particle_mass[]; };       // [particle_count], kg
layout(std430, binding = 2) readonly buffer Environment { Real environment[]; };  // gravity x, y, z (m/s^2; 0 when off), drag (kg/s; 0 when off)
layout(std430, binding = 3) readonly buffer GatherOffset { uint gather_offset[]; };  // [particle_count + 1]
layout(std430, binding = 4) readonly buffer GatherSlot { uint gather_slot[]; };      // [force_slot_count]
layout(std430, binding = 5) readonly buffer SlotForce { Real slot_force[]; };        // [3 force_slot_count], N
layout(std430, binding = 6) writeonly buffer Force { Real force[]; };                // [3 particle_count], N

layout(push_constant) uniform Constants { GatherConstants constants; };

#include "gpu/shaders/gather.glsl"

void main() {
  const uint p = invocation_index();
  if (p >= constants.particle_count) return;
  const Vec3 sum = gathered_force(p, Vec3(velocity[3 * p], velocity[3 * p + 1], velocity[3 * p + 2]));
  force[3 * p] = sum.x;
  force[3 * p + 1] = sum.y;
  force[3 * p + 2] = sum.z;
}
