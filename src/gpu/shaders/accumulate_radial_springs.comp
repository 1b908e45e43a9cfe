#version 450
#extension GL_GOOGLE_include_directive : require
// accumulate_radial_springs (src/forces/radial_springs.cpp) on the device: one invocation per
// radial spring writes its three force slots (3r: the centre, 3r+1: b, 3r+2: c, after slot_base)
// and its damping power; zeros for a spring that is broken or whose term (adjacent or opposite)
// is off. The formula is element_math.inc's radial_force, the CPU's own text, with its handling of
// straight and folded pairs (the singular sine) and its fade of vanishing arms (the fade lengths
// of forces.h's radial_fade_lengths).
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/element_pass.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Position { Real position[]; };           // [3 particle_count], m
layout(std430, binding = 1) readonly buffer Velocity { Real velocity[]; };           // [3 particle_count], m/s
layout(std430, binding = 2) readonly buffer Particles { uint radial_particles[]; };  // [3 radial_count]: centre, b, c
layout(std430, binding = 3) readonly buffer RestAngle { Real radial_rest_angle[]; };  // rad
layout(std430, binding = 4) readonly buffer Stiffness { Real radial_stiffness[]; };   // N m/rad
layout(std430, binding = 5) readonly buffer Damping { Real radial_damping[]; };       // N m s/rad
layout(std430, binding = 6) readonly buffer FadeLength { Real radial_fade_length[]; };  // [2 radial_count]: b, c arms, m
layout(std430, binding = 7) readonly buffer Active { uint radial_active[]; };  // not 0: live and its term on
layout(std430, binding = 8) writeonly buffer SlotForce { Real slot_force[]; };  // [3 force_slot_count], N
layout(std430, binding = 9) writeonly buffer ElementPower { Real element_power[]; };  // [connectors + radials], W
layout(std430, binding = 10) readonly buffer OriginPosition { Real origin_position[]; };  // the step's start, m
layout(std430, binding = 11) readonly buffer OriginVelocity { Real origin_velocity[]; };  // m/s

layout(push_constant) uniform Constants { ElementPassConstants constants; };

#include "gpu/shaders/stage_offsets.glsl"

void store_slot(uint slot, Vec3 force) {
  slot_force[3 * slot] = force.x;
  slot_force[3 * slot + 1] = force.y;
  slot_force[3 * slot + 2] = force.z;
}

void main() {
  const uint r = invocation_index();
  if (r >= constants.element_count) return;
  const uint slot = constants.slot_base + 3 * r;
  if (radial_active[r] == 0u) {
    store_slot(slot, Vec3(0.0));
    store_slot(slot + 1, Vec3(0.0));
    store_slot(slot + 2, Vec3(0.0));
    element_power[constants.power_base + r] = Real(0.0);
    return;
  }
  const uint centre = radial_particles[3 * r];
  const uint b = radial_particles[3 * r + 1];
  const uint c = radial_particles[3 * r + 2];
  const Real damping = constants.damped != 0u ? radial_damping[r] : Real(0.0);
  // Near the centre: in float32, relative to it (stage_offsets.glsl).
  const RadialForce f = radial_force(stage_position_near(centre, centre), stage_position_near(b, centre),
                                     stage_position_near(c, centre), stage_velocity_near(centre, centre),
                                     stage_velocity_near(b, centre), stage_velocity_near(c, centre),
                                     radial_rest_angle[r], radial_stiffness[r], damping, radial_fade_length[2 * r],
                                     radial_fade_length[2 * r + 1]);
  store_slot(slot, -(f.force_on_b + f.force_on_c));
  store_slot(slot + 1, f.force_on_b);
  store_slot(slot + 2, f.force_on_c);
  element_power[constants.power_base + r] = f.damping_power;
}
