#version 450
#extension GL_GOOGLE_include_directive : require
// accumulate_connector_springs (src/forces/connector_springs.cpp) on the device: one invocation
// per connector writes its two force slots (2e: on a, 2e+1: on b, after slot_base) and its
// damping power; zeros for a connector that is broken or whose term is off. From
// the same structure-of-arrays as the CPU (Vec3 arrays as 3 Reals each, uploaded unchanged in
// float64). The formula is element_math.inc's connector_force, the CPU's own text.
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/element_pass.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Position { Real position[]; };           // [3 particle_count], m
layout(std430, binding = 1) readonly buffer Velocity { Real velocity[]; };           // [3 particle_count], m/s
layout(std430, binding = 2) readonly buffer Particles { uint connector_particles[]; };  // [2 connector_count]
layout(std430, binding = 3) readonly buffer RestLength { Real connector_rest_length[]; };  // m
layout(std430, binding = 4) readonly buffer Stiffness { Real connector_stiffness[]; };     // N/m
layout(std430, binding = 5) readonly buffer Damping { Real connector_damping[]; };         // N s/m
layout(std430, binding = 6) readonly buffer Active { uint connector_active[]; };  // 1: live and its term on
layout(std430, binding = 7) writeonly buffer SlotForce { Real slot_force[]; };  // [3 force_slot_count], N
layout(std430, binding = 8) writeonly buffer ElementPower { Real element_power[]; };  // [connectors + radials], W
layout(std430, binding = 9) readonly buffer OriginPosition { Real origin_position[]; };  // the step's start, m
layout(std430, binding = 10) readonly buffer OriginVelocity { Real origin_velocity[]; };  // m/s

layout(push_constant) uniform Constants { ElementPassConstants constants; };

#include "gpu/shaders/stage_offsets.glsl"

void store_slot(uint slot, Vec3 force) {
  slot_force[3 * slot] = force.x;
  slot_force[3 * slot + 1] = force.y;
  slot_force[3 * slot + 2] = force.z;
}

void main() {
  const uint e = invocation_index();
  if (e >= constants.element_count) return;
  const uint slot = constants.slot_base + 2 * e;
  if (connector_active[e] == 0u) {
    store_slot(slot, Vec3(0.0));
    store_slot(slot + 1, Vec3(0.0));
    element_power[constants.power_base + e] = Real(0.0);
    return;
  }
  const uint a = connector_particles[2 * e];
  const uint b = connector_particles[2 * e + 1];
  const Real damping = constants.damped != 0u ? connector_damping[e] : Real(0.0);
  // Near a: in float32, relative to a (stage_offsets.glsl).
  const ConnectorForce f =
      connector_force(stage_position_near(a, a), stage_position_near(b, a), stage_velocity_near(a, a),
                      stage_velocity_near(b, a), connector_rest_length[e], connector_stiffness[e], damping);
  store_slot(slot, f.force_on_a);
  store_slot(slot + 1, -f.force_on_a);
  element_power[constants.power_base + e] = f.damping_power;
}
