#version 450
#extension GL_GOOGLE_include_directive : require
// One stage of a Runge-Kutta attempt on a lattice sheet in one pass: the work of rk_stage_state,
// lattice_elements and stage_acceleration, without the stage state and the springs' forces going
// through device memory between them. Each particle forms the stage state of the particles its
// springs and its neighbours' springs reach, two lattice cells at most (stage_state.glsl), sums
// its own springs' forces on it and each neighbour's springs' forces on it
// (lattice_spring_sums.glsl: the neighbour's springs that act on it, the same terms in the same
// order as the neighbour's own sum), and writes K_i and its powers (stage_acceleration.glsl).
// The same bits as the three passes, for three times the springs' arithmetic and a third of the
// dispatches: the device is bound by memory and by the dispatches' latency, not by arithmetic
// (docs/gpu.md, "One pass per stage").
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/device_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Position { Real origin_position[]; };  // the state, [3 particles], m
layout(std430, binding = 1) readonly buffer Velocity { Real origin_velocity[]; };  // m/s
layout(std430, binding = 2) readonly buffer PositionLow { Real origin_position_low[]; };  // float32: low parts
layout(std430, binding = 3) readonly buffer VelocityLow { Real origin_velocity_low[]; };
// [stages][3 particles], m/s^2: the earlier stages' read, this stage's written.
layout(std430, binding = 4) buffer Acceleration { Real acceleration[]; };
layout(std430, binding = 5) readonly buffer Rows { Real rows[]; };  // the method's Nystrom rows
layout(std430, binding = 6) readonly buffer ControlReal { Real control_real[]; };
layout(std430, binding = 7) readonly buffer ControlUint { uint control_uint[]; };
layout(std430, binding = 8) readonly buffer ParticleAnchor { int particle_anchor[]; };  // anchor row, or -1
layout(std430, binding = 9) readonly buffer AnchorPaths { Real anchor_paths[]; };
layout(std430, binding = 10) readonly buffer Params { Real lattice_params[]; };      // [particles][kLatticeParams]
layout(std430, binding = 11) readonly buffer EventParams { Real event_params[]; };  // [particles][kEventParams]
layout(std430, binding = 12) readonly buffer Mass { Real particle_mass[]; };        // kg
layout(std430, binding = 13) readonly buffer InverseMass { Real inverse_mass[]; };  // 1/kg; 0 anchored
layout(std430, binding = 14) readonly buffer Environment { Real environment[]; };   // gravity (3), drag
layout(std430, binding = 15) buffer ParticlePower { Real particle_power[]; };  // [3][particles], W (device_step.h)

layout(push_constant) uniform Constants { LatticePassConstants constants; };

#include "gpu/shaders/stage_state.glsl"
#define CLOTHSIM_STAGE_COMPUTED
StagePoint stage_offset_point(uint q) { return stage_state(q, constants.stage); }
#include "gpu/shaders/stage_offsets.glsl"
#include "gpu/shaders/lattice_spring_sums.glsl"
#include "gpu/shaders/stage_acceleration.glsl"

void main() {
  const uint p = invocation_index();
  const uint n = constants.particle_count;
  if (p >= n || control_uint[kActive] == 0u) return;
  const LatticeCell cell = lattice_cell(p, constants.rows, constants.cols);
  const LatticeSpringSums own = particle_spring_sums(p, kEveryArm);
  // Neighbour d's springs on p, which are on its arm (d + 2) % 4: lattice_elements' slot of it.
  Vec3 from[4];
  for (uint d = 0u; d < 4u; ++d) {
    const uint arm = (d + 2u) % 4u;
    from[d] = cell.has[d] ? particle_spring_sums(cell.neighbour[d], arm).to[arm] : Vec3(0.0);
  }
  // Weighed by the solution row, summed over the stages (device_step.h), as lattice_elements does.
  const Real weight = rows[solution_weight_slot(constants.stages, constants.stage)];
  particle_power[2u * n + p] = (constants.stage == 0u ? Real(0.0) : particle_power[2u * n + p]) + weight * own.power;
  const Vec3 v = stage_velocity_from(p, stage_offset_point(p).velocity);
  store_stage_acceleration(p, v, lattice_force_on(p, v, own.own, cell.has, from));
}
