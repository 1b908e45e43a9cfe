#version 450
#extension GL_GOOGLE_include_directive : require
// One stage of a Runge-Kutta attempt on a lattice sheet in one pass: the work of rk_stage_state,
// lattice_elements and stage_acceleration, without the stage state and the springs' forces going
// through device memory between them. A workgroup takes a tile of kTile x kTile particles and,
// in its shared memory:
//   1. forms the stage state (stage_state.glsl) of the tile and two cells around it, all that the
//      tile's springs and its neighbours' springs reach;
//   2. sums the springs (lattice_spring_sums.glsl) of each tile particle, and of each particle on
//      the ring around the tile those that act on the tile (the same terms in the same order as
//      that particle's own sum);
//   3. gathers each tile particle's force from its own sum and its neighbours' shares, and writes
//      K_i and its powers (stage_acceleration.glsl);
//   4. in the attempt's last stage, forms with K_i at hand the trial state and its scaled error
//      (rk_trial.glsl, rk_solution's work) and the tile's largest error for rk_control.
// The same bits as the three passes, with the tile's edges formed twice (2.25 times the stage
// states and 1.25 times the radial springs of the three passes, at 8 x 8) and a third of the
// dispatches (docs/gpu.md, "One pass per stage").
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/device_step.h"

const uint kTile = kStageTile;  // device_step.h
const uint kWorkgroupSize = kTile * kTile;
layout(local_size_x = 64) in;  // kWorkgroupSize: ComputePipeline's default size, which dispatch() counts by
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
// The last stage's: the trial state (float32: its low parts too) and each tile's largest error.
layout(std430, binding = 16) writeonly buffer TrialPosition { Real trial_position[]; };
layout(std430, binding = 17) writeonly buffer TrialVelocity { Real trial_velocity[]; };
layout(std430, binding = 18) writeonly buffer BlockError { Real block_error[]; };
layout(std430, binding = 19) writeonly buffer BlockParticle { uint block_particle[]; };
layout(std430, binding = 20) writeonly buffer TrialPositionLow { Real trial_position_low[]; };
layout(std430, binding = 21) buffer TrialVelocityLow { Real trial_velocity_low[]; };

layout(push_constant) uniform Constants { LatticePassConstants constants; };

#include "gpu/shaders/stage_state.glsl"

// The tile with two cells around it (kHalo x kHalo) and with one (kRing x kRing), from the
// tile's first row and column less two and one.
const uint kHalo = kTile + 4u;
const uint kRing = kTile + 2u;
shared Real halo_position[3u * kHalo * kHalo];  // stage states (float32: offsets from the state)
shared Real halo_velocity[3u * kHalo * kHalo];
shared Real ring_shares[12u * kRing * kRing];  // each particle's springs' forces on its four arms
uint tile_row;                                 // the tile's first lattice row and column
uint tile_col;

uint halo_slot(uint q) { return (q / constants.cols + 2u - tile_row) * kHalo + (q % constants.cols + 2u - tile_col); }
uint ring_slot(uint row, uint col) { return (row + 1u - tile_row) * kRing + (col + 1u - tile_col); }

#define CLOTHSIM_STAGE_COMPUTED
StagePoint stage_offset_point(uint q) {
  const uint slot = 3u * halo_slot(q);
  StagePoint point;
  point.position = Vec3(halo_position[slot], halo_position[slot + 1u], halo_position[slot + 2u]);
  point.velocity = Vec3(halo_velocity[slot], halo_velocity[slot + 1u], halo_velocity[slot + 2u]);
  return point;
}
#include "gpu/shaders/stage_offsets.glsl"
#include "gpu/shaders/lattice_spring_sums.glsl"
#include "gpu/shaders/stage_acceleration.glsl"

Vec3 last_acceleration;  // the last stage's K of this invocation's particle, not written out
Vec3 trial_acceleration(uint l, uint p) {
  return l == constants.stage ? last_acceleration : stage_acceleration_of(l, p);
}
#define CLOTHSIM_REDUCE_SIZE kWorkgroupSize
#include "gpu/shaders/rk_trial.glsl"

void store_share(uint row, uint col, uint arm, Vec3 force) {
  const uint at = 12u * ring_slot(row, col) + 3u * arm;
  ring_shares[at] = force.x;
  ring_shares[at + 1u] = force.y;
  ring_shares[at + 2u] = force.z;
}

Vec3 share(uint row, uint col, uint arm) {
  const uint at = 12u * ring_slot(row, col) + 3u * arm;
  return Vec3(ring_shares[at], ring_shares[at + 1u], ring_shares[at + 2u]);
}

void main() {
  if (control_uint[kActive] == 0u) return;  // the same for the whole dispatch, before any barrier
  const uint lattice_rows = constants.rows;
  const uint cols = constants.cols;
  const uint tiles_across = (cols + kTile - 1u) / kTile;
  const uint tile = workgroup_index();
  tile_row = (tile / tiles_across) * kTile;
  tile_col = (tile % tiles_across) * kTile;
  const uint local = gl_LocalInvocationID.x;

  // 1. The stage states of the tile and two cells around it (rows and columns before the tile's
  // first as unsigned numbers past the lattice).
  for (uint slot = local; slot < kHalo * kHalo; slot += kWorkgroupSize) {
    const uint row = tile_row + slot / kHalo - 2u;
    const uint col = tile_col + slot % kHalo - 2u;
    if (row >= lattice_rows || col >= cols) continue;
    const StagePoint point = stage_state(row * cols + col, constants.stage);
    for (uint k = 0u; k < 3u; ++k) {
      halo_position[3u * slot + k] = point.position[k];
      halo_velocity[3u * slot + k] = point.velocity[k];
    }
  }
  barrier();

  // 2. This invocation's tile particle's springs, and one particle of the ring's springs on the
  // tile (the ring's kTile particles on each side, corners excluded: they touch no tile particle).
  const uint row = tile_row + local / kTile;
  const uint col = tile_col + local % kTile;
  const bool inside = row < lattice_rows && col < cols;
  const uint p = row * cols + col;
  LatticeSpringSums own;
  if (inside) {
    own = particle_spring_sums(p, kEveryArm);
    for (uint d = 0u; d < 4u; ++d) store_share(row, col, d, own.to[d]);
  }
  if (local < 4u * kTile) {
    const uint side = local / kTile;  // 0 north, 1 south, 2 west, 3 east of the tile
    const uint along = local % kTile;
    const uint ring_row = side == 0u ? tile_row - 1u : (side == 1u ? tile_row + kTile : tile_row + along);
    const uint ring_col = side < 2u ? tile_col + along : (side == 2u ? tile_col - 1u : tile_col + kTile);
    const uint arm = side == 0u ? 1u : (side == 1u ? 3u : (side == 2u ? 0u : 2u));  // toward the tile
    if (ring_row < lattice_rows && ring_col < cols) {
      store_share(ring_row, ring_col, arm, particle_spring_sums(ring_row * cols + ring_col, arm).to[arm]);
    }
  }
  barrier();

  // 3. The force on the tile particle: gravity and drag, its own springs, then each neighbour's
  // share on its arm toward p, (d + 2) % 4: lattice_elements' slot of it.
  const bool last = constants.stage + 1u == constants.stages;
  if (inside) {
    const LatticeCell cell = lattice_cell(p, lattice_rows, cols);
    Vec3 from[4];
    from[0] = cell.has[0] ? share(row, col + 1u, 2u) : Vec3(0.0);
    from[1] = cell.has[1] ? share(row + 1u, col, 3u) : Vec3(0.0);
    from[2] = cell.has[2] ? share(row, col - 1u, 0u) : Vec3(0.0);
    from[3] = cell.has[3] ? share(row - 1u, col, 1u) : Vec3(0.0);
    // Weighed by the solution row, summed over the stages (device_step.h), as lattice_elements does.
    const uint n = constants.particle_count;
    const Real weight = rows[solution_weight_slot(constants.stages, constants.stage)];
    particle_power[2u * n + p] = (constants.stage == 0u ? Real(0.0) : particle_power[2u * n + p]) + weight * own.power;
    const Vec3 v = stage_velocity_from(p, stage_offset_point(p).velocity);
    const Vec3 force = lattice_force_on(p, v, own.own, cell.has, from);
    if (last) {
      last_acceleration = acceleration_and_powers(p, v, force);
    } else {
      store_stage_acceleration(p, v, force);
    }
  }
  if (!last) return;

  // 4. The trial state and its error (rk_solution's, the same bits), and the tile's largest error.
  Real ratio = Real(0.0);
  if (inside) {
    StepStart start;
    start.x0 = state_vector(0u, p);
    start.v0 = state_vector(1u, p);
#if CLOTHSIM_STAGE_OFFSETS
    start.low_x0 = state_low_vector(0u, p);
    start.low_v0 = state_low_vector(1u, p);
#endif
    ratio = trial_and_error(p, constants.symplectic != 0u, start);
  }
  reduce_largest_error(ratio, inside ? p : 0xffffffffu);
  if (local == 0u) {
    block_error[tile] = largest_error[0];
    block_particle[tile] = largest_particle[0];
  }
}
