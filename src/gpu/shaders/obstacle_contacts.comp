#version 450
#extension GL_GOOGLE_include_directive : require
// The obstacle pass on the device (ObstacleContacts::apply on the CPU): when rk_control accepted
// the attempt, each free particle of the trial state is resolved against every collider in
// index order, with the CPU's contact law (collision/obstacle_contact.inc) and shapes
// (model/collider_shapes.inc). A particle the pass moves keeps its unresolved state in
// `contact_before`, for obstacle_energy to book the change, and is flagged in `moved`; its trial
// state becomes the resolved one, which rk_accept then takes. Each invocation writes only its own
// particle's entries.
// Implicit Euler's device step runs it too (gpu/device_implicit_obstacles.cpp), on its state after
// the step, with `holds`: a particle it held on a surface during the step (`hold`) has friction act
// on the normal impulse that surface exerted (`impulse`), as the CPU's pass does with the impulses
// implicit Euler writes into model/surface_contacts.h.
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/device_step.h"
#include "gpu/shaders/implicit_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer ControlReal { Real control_real[]; };
layout(std430, binding = 1) readonly buffer ControlUint { uint control_uint[]; };
layout(std430, binding = 2) readonly buffer Position { Real position[]; };  // the step's start, m
layout(std430, binding = 3) buffer TrialPosition { Real trial_position[]; };  // m
layout(std430, binding = 4) buffer TrialVelocity { Real trial_velocity[]; };  // m/s
layout(std430, binding = 5) readonly buffer ParticleAnchor { int particle_anchor[]; };
layout(std430, binding = 6) readonly buffer Colliders { Real colliders[]; };  // [colliders][kColliderReals]
layout(std430, binding = 7) writeonly buffer ContactBefore { Real contact_before[]; };  // [6 particles]: x, v
layout(std430, binding = 8) writeonly buffer Moved { uint moved[]; };                  // [particles]
layout(std430, binding = 9) readonly buffer MeshReals { Real mesh_reals[]; };  // device_step.h, kMeshHeaderUints
layout(std430, binding = 10) readonly buffer MeshUints { uint mesh_uints[]; };
layout(std430, binding = 11) writeonly buffer TrialPositionLow { Real trial_position_low[]; };  // float32
layout(std430, binding = 12) writeonly buffer TrialVelocityLow { Real trial_velocity_low[]; };
// With `holds` (placeholders else): the surface contacts of the step's start, [particles][kContactReals]
// (implicit_step.h: the collider's index + 1 in the last), the surface impulses, the holds, the masses.
layout(std430, binding = 13) readonly buffer SurfaceContacts { Real surface_contacts[]; };
layout(std430, binding = 14) readonly buffer Impulse { Real impulse[]; };  // [3 particles], N s
layout(std430, binding = 15) readonly buffer Hold { uint hold[]; };        // [particles], kHold*
layout(std430, binding = 16) readonly buffer Mass { Real particle_mass[]; };  // kg

layout(push_constant) uniform Constants { ObstaclePassConstants constants; };

#include "gpu/shaders/obstacle_surface.glsl"

void main() {
  const uint p = invocation_index();
  if (p >= constants.particle_count || control_uint[kAccepted] == 0u) return;
  moved[p] = 0u;
  if (particle_anchor[p] >= 0) return;
  const Real tau0 = control_real[kStepStart];
  const Real tau1 = control_real[kElapsed];
  const Real thickness = control_real[kThickness];
  const Vec3 x = Vec3(trial_position[3 * p], trial_position[3 * p + 1], trial_position[3 * p + 2]);
  const Vec3 v = Vec3(trial_velocity[3 * p], trial_velocity[3 * p + 1], trial_velocity[3 * p + 2]);
  const Vec3 start = Vec3(position[3 * p], position[3 * p + 1], position[3 * p + 2]);
  ParticleContact particle;
  particle.position = x;
  particle.velocity = v;
  particle.touched = false;
  // The normal velocity change a held particle's surface made, m/s (ObstacleContacts::apply).
  Real held = Real(0.0);
  uint held_on = 0u;  // the collider's index + 1
  if (constants.holds != 0u && hold[p] != kHoldNone) {
    const uint row = kContactReals * p;
    const Vec3 n = Vec3(surface_contacts[row], surface_contacts[row + 1], surface_contacts[row + 2]);
    const Vec3 surface_impulse = Vec3(impulse[3 * p], impulse[3 * p + 1], impulse[3 * p + 2]);
    held = max(Real(0.0), dot(n, surface_impulse)) * (Real(1.0) / particle_mass[p]);
    held_on = uint(surface_contacts[row + kContactResting]);
  }
  for (uint c = 0u; c < constants.colliders; ++c) {
    const ObstacleAtStepEnd obstacle = obstacle_at(c, tau1);
    // The start carried into the collider's frame: moved by the collider's motion over the step.
    const Vec3 start_in_frame = start + (obstacle.offset - collider_offset(c, tau0));
    resolve_obstacle_contact(colliders[c * kColliderReals + kColliderFriction], thickness, tau1 - tau0, obstacle,
                             start_in_frame, held_on == c + 1u ? held : Real(0.0), particle);
  }
  if (!particle.touched) return;
  moved[p] = 1u;
  for (uint k = 0u; k < 3u; ++k) {
    contact_before[6 * p + k] = x[k];
    contact_before[6 * p + 3 + k] = v[k];
    trial_position[3 * p + k] = particle.position[k];
    trial_velocity[3 * p + k] = particle.velocity[k];
#if CLOTHSIM_STAGE_OFFSETS
    // A moved particle's state is the contact's, in float (split_state.glsl: low parts of zero).
    trial_position_low[3 * p + k] = Real(0.0);
    trial_velocity_low[3 * p + k] = Real(0.0);
#endif
  }
}
