#version 450
#extension GL_GOOGLE_include_directive : require
// Consecutive stages of a Runge-Kutta attempt on a lattice sheet in one pass: for each, the work
// of rk_stage_state, lattice_elements and stage_acceleration, without the stage states, the
// springs' forces or (between the pass's own stages) the accelerations going through device
// memory. A workgroup takes a tile of kTile x kTile particles. A stage's force on a particle
// reaches two cells, so for the pass's stage j of G, K_j is formed on the tile and
// reach_j = 2 (G - 1 - j) cells around it, all that the pass's later stages reach; for each stage,
// in shared memory:
//   1. the stage states (stage_state.glsl) of that region and two cells around it, with the pass's
//      earlier stages' accelerations from shared memory and the earlier passes' from the stages'
//      arrays;
//   2. the springs' sums (lattice_spring_sums.glsl) of each particle of the region, and of each
//      particle on the ring around it those that act on the region (the same terms in the same
//      order as that particle's own sum);
//   3. each particle's force gathered from its own sum and its neighbours' shares, and K_j: kept
//      in shared memory for the pass's later stages, and for the tile's particles written with
//      their powers (stage_acceleration.glsl);
//   4. after the attempt's last stage, with its K at hand, the trial state and its scaled error
//      (rk_trial.glsl, rk_solution's work) and the tile's largest error for rk_control.
// The same bits as the three passes a stage; the cells around the tile are formed again by each
// tile that reaches them (docs/gpu.md, "One pass per stage", "Stages chained in a pass").
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
// [stages][3 particles], m/s^2: the earlier passes' read, the pass's own written.
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

// The stages a pass can chain (device_step.h; at most 3), and the regions at the most:
// the first stage's states reach 2 G cells around the tile, its springs' sums 2 G - 1, its K 2 G - 2.
#if CLOTHSIM_FLOAT64
const uint kChain = kMaxChainedStagesFloat64;
#else
const uint kChain = kMaxChainedStagesFloat32;
#endif
const uint kStateSide = kTile + 4u * kChain;
const uint kShareSide = kStateSide - 2u;
shared Real halo_position[3u * kStateSide * kStateSide];  // stage states (float32: offsets from the state)
shared Real halo_velocity[3u * kStateSide * kStateSide];
shared Real ring_shares[12u * kShareSide * kShareSide];  // each particle's springs' forces on its four arms
// The pass's stages but its last: K on the tile and its reach, stage j after stage j - 1's.
const uint kChainAccelerations =
    kChain == 1u ? 1u : 3u * ((kChain == 3u ? (kTile + 8u) * (kTile + 8u) : 0u) + (kTile + 4u) * (kTile + 4u));
shared Real chain_acceleration[kChainAccelerations];
// A region's particles an invocation takes at the most: K's region of the first stage.
const uint kPerInvocation = ((kTile + 4u * kChain - 4u) * (kTile + 4u * kChain - 4u) + kWorkgroupSize - 1u) /
                            kWorkgroupSize;

// The tile's particles' power sums over the stages (device_step.h's three, drag, anchors and
// damping, by invocation), kept here between the pass's stages, which take a particle in
// different invocations.
shared Real tile_power[3u * kWorkgroupSize];

uint tile_row;  // the tile's first lattice row and column
uint tile_col;
uint state_reach;  // the current stage's regions around the tile: its states', its springs' sums'
uint sum_reach;

// Slot of lattice (row, col) in a square region `reach` cells around the tile (rows and columns
// before the tile's as unsigned numbers past the lattice, the same arithmetic both ways).
uint region_slot(uint row, uint col, uint reach) {
  return (row + reach - tile_row) * (kTile + 2u * reach) + (col + reach - tile_col);
}

// Where the pass's stage j keeps its K: after the earlier stages' regions.
uint chain_slot(uint j, uint row, uint col) {
  uint base = 0u;
  for (uint k = 0u; k < j; ++k) {
    const uint side = kTile + 4u * (constants.pass_stages - 1u - k);
    base += side * side;
  }
  return 3u * (base + region_slot(row, col, 2u * (constants.pass_stages - 1u - j)));
}

#include "gpu/shaders/stage_accelerations.glsl"
Vec3 last_acceleration;  // the attempt's last stage's K of this invocation's tile particle
// K_l of particle p for a stage state or the trial state: the earlier passes' from the stages'
// arrays, this pass's own from shared memory, the attempt's last stage's (which only the trial
// state reads, for this invocation's particle) from the register.
Vec3 formed_acceleration(uint l, uint p) {
  if (l < constants.stage) return stage_acceleration_of(l, p);
  if (l + 1u == constants.stages) return last_acceleration;
  const uint at = chain_slot(l - constants.stage, p / constants.cols, p % constants.cols);
  return Vec3(chain_acceleration[at], chain_acceleration[at + 1u], chain_acceleration[at + 2u]);
}
#define CLOTHSIM_STAGE_ACCELERATION formed_acceleration
#include "gpu/shaders/stage_state.glsl"

#define CLOTHSIM_STAGE_COMPUTED
StagePoint stage_offset_point(uint q) {
  const uint slot = 3u * region_slot(q / constants.cols, q % constants.cols, state_reach);
  StagePoint point;
  point.position = Vec3(halo_position[slot], halo_position[slot + 1u], halo_position[slot + 2u]);
  point.velocity = Vec3(halo_velocity[slot], halo_velocity[slot + 1u], halo_velocity[slot + 2u]);
  return point;
}
#include "gpu/shaders/stage_offsets.glsl"
#include "gpu/shaders/lattice_spring_sums.glsl"
#include "gpu/shaders/stage_acceleration.glsl"

#define CLOTHSIM_REDUCE_SIZE kWorkgroupSize
#include "gpu/shaders/rk_trial.glsl"

void store_share(uint row, uint col, uint arm, Vec3 force) {
  const uint at = 12u * region_slot(row, col, sum_reach) + 3u * arm;
  ring_shares[at] = force.x;
  ring_shares[at + 1u] = force.y;
  ring_shares[at + 2u] = force.z;
}

Vec3 share(uint row, uint col, uint arm) {
  const uint at = 12u * region_slot(row, col, sum_reach) + 3u * arm;
  return Vec3(ring_shares[at], ring_shares[at + 1u], ring_shares[at + 2u]);
}

// The pass's stage j (the attempt's stage constants.stage + j), K formed `reach` cells around the
// tile. Every invocation calls it: its barriers are the workgroup's.
void chained_stage(uint j, uint reach) {
  const uint stage = constants.stage + j;
  const uint lattice_rows = constants.rows;
  const uint cols = constants.cols;
  const uint local = gl_LocalInvocationID.x;
  state_reach = reach + 2u;
  sum_reach = reach + 1u;

  // 1. The stage states of the region and two cells around it.
  const uint state_side = kTile + 2u * state_reach;
  for (uint slot = local; slot < state_side * state_side; slot += kWorkgroupSize) {
    const uint row = tile_row + slot / state_side - state_reach;
    const uint col = tile_col + slot % state_side - state_reach;
    if (row >= lattice_rows || col >= cols) continue;
    const StagePoint point = stage_state(row * cols + col, stage);
    for (uint k = 0u; k < 3u; ++k) {
      halo_position[3u * slot + k] = point.position[k];
      halo_velocity[3u * slot + k] = point.velocity[k];
    }
  }
  barrier();

  // 2. The springs of each particle of the region (its own sum kept by the invocation that takes
  // it, in the same order in step 3), and of each particle on the ring around it, corners
  // excluded, those on the region.
  const uint side = kTile + 2u * reach;
  Vec3 own[kPerInvocation];
  Real own_power[kPerInvocation];
  // The region's slots this invocation takes: a count bounded by a constant, which a GPU's
  // compiler unrolls to keep `own` in registers, and which lavapipe runs as a short loop (the
  // constant count alone, unrolled, ran it twice as slowly).
  const uint count = (side * side + kWorkgroupSize - 1u) / kWorkgroupSize;
  for (uint i = 0u; i < kPerInvocation && i < count; ++i) {
    const uint slot = local + i * kWorkgroupSize;
    const uint row = tile_row + slot / side - reach;
    const uint col = tile_col + slot % side - reach;
    if (slot >= side * side || row >= lattice_rows || col >= cols) continue;
    const LatticeSpringSums sums = particle_spring_sums(row * cols + col, kEveryArm);
    own[i] = sums.own;
    own_power[i] = sums.power;
    for (uint d = 0u; d < 4u; ++d) store_share(row, col, d, sums.to[d]);
  }
  for (uint item = local; item < 4u * side; item += kWorkgroupSize) {
    const uint edge = item / side;  // 0 north, 1 south, 2 west, 3 east of the region
    const uint along = item % side;
    const uint first_row = tile_row - reach;
    const uint first_col = tile_col - reach;
    const uint ring_row = edge == 0u ? first_row - 1u : (edge == 1u ? first_row + side : first_row + along);
    const uint ring_col = edge < 2u ? first_col + along : (edge == 2u ? first_col - 1u : first_col + side);
    const uint arm = edge == 0u ? 1u : (edge == 1u ? 3u : (edge == 2u ? 0u : 2u));  // toward the region
    if (ring_row < lattice_rows && ring_col < cols) {
      store_share(ring_row, ring_col, arm, particle_spring_sums(ring_row * cols + ring_col, arm).to[arm]);
    }
  }
  barrier();

  // 3. The force on each particle of the region: gravity and drag, its own springs, then each
  // neighbour's share on its arm toward p, (d + 2) % 4: lattice_elements' slot of it. Then K.
  const bool last = stage + 1u == constants.stages;
  for (uint i = 0u; i < kPerInvocation && i < count; ++i) {
    const uint slot = local + i * kWorkgroupSize;
    const uint row = tile_row + slot / side - reach;
    const uint col = tile_col + slot % side - reach;
    if (slot >= side * side || row >= lattice_rows || col >= cols) continue;
    const uint p = row * cols + col;
    const LatticeCell cell = lattice_cell(p, lattice_rows, cols);
    Vec3 from[4];
    from[0] = cell.has[0] ? share(row, col + 1u, 2u) : Vec3(0.0);
    from[1] = cell.has[1] ? share(row + 1u, col, 3u) : Vec3(0.0);
    from[2] = cell.has[2] ? share(row, col - 1u, 0u) : Vec3(0.0);
    from[3] = cell.has[3] ? share(row - 1u, col, 1u) : Vec3(0.0);
    const Vec3 v = stage_velocity_from(p, stage_offset_point(p).velocity);
    const StageAcceleration k = stage_acceleration_from(p, stage, v, lattice_force_on(p, v, own[i], cell.has, from));
    if (j + 1u < constants.pass_stages) {
      const uint at = chain_slot(j, row, col);
      for (uint c = 0u; c < 3u; ++c) chain_acceleration[at + c] = k.a[c];
    }
    if (row - tile_row >= kTile || col - tile_col >= kTile) continue;  // another tile's
    // The tile's particle: its powers, weighed by the solution row and summed over the stages
    // (device_step.h), as lattice_elements and stage_acceleration add them.
    const uint sums = 3u * ((row - tile_row) * kTile + (col - tile_col));
    add_stage_powers(stage, v, k.anchor_power, tile_power[sums], tile_power[sums + 1u]);
    const Real weight = rows[solution_weight_slot(constants.stages, stage)];
    tile_power[sums + 2u] = (stage == 0u ? Real(0.0) : tile_power[sums + 2u]) + weight * own_power[i];
    if (last) {
      last_acceleration = k.a;
    } else {
      store_acceleration(p, stage, k.a);
    }
  }
  barrier();
}

void main() {
  if (control_uint[kActive] == 0u) return;  // the same for the whole dispatch, before any barrier
  const uint tiles_across = (constants.cols + kTile - 1u) / kTile;
  const uint tile = workgroup_index();
  tile_row = (tile / tiles_across) * kTile;
  tile_col = (tile % tiles_across) * kTile;
  const uint local = gl_LocalInvocationID.x;
  const uint row = tile_row + local / kTile;  // the tile particle this invocation loads and stores
  const uint col = tile_col + local % kTile;
  const bool inside = row < constants.rows && col < constants.cols;
  const uint p = row * constants.cols + col;
  const uint n = constants.particle_count;
  if (inside && constants.stage != 0u) {
    for (uint k = 0u; k < 3u; ++k) tile_power[3u * local + k] = particle_power[k * n + p];
  }
  barrier();
  for (uint j = 0u; j < constants.pass_stages; ++j) chained_stage(j, 2u * (constants.pass_stages - 1u - j));
  if (inside) {
    for (uint k = 0u; k < 3u; ++k) particle_power[k * n + p] = tile_power[3u * local + k];
  }
  if (constants.stage + constants.pass_stages != constants.stages) return;

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
