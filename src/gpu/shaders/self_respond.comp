#version 450
#extension GL_GOOGLE_include_directive : require
// Self-collision's responses on the device (gpu/device_self_contacts.h), over a list of flagged
// candidates: the near pairs (stage 2) or the touching ones (stage 3). The CPU's responses
// (SelfContacts::resolve_proximity, resolve_impacts) run one pair after another in candidate
// order; here each round computes every listed pair's change from the round's start, and each
// particle then adds its pairs' changes in pair order, through a table from particles to their
// pairs: a Jacobi iteration with the CPU's response law. A particle in n pairs would take n
// changes that each ask for the whole of a pair's correction, so each pair's change is scaled by
// its share, 1 / the most pairs any of its free particles is in (mass splitting: Tonge, Benevolenskiy
// and Voroshilov, "Mass splitting for jitter-free parallel rigid body simulation", SIGGRAPH 2012);
// the share is the same for the pair's 4 particles, so each change keeps the pair's momentum.
// Phases (self_step.h, kRespond*):
//   count, fill, sort   the table: each particle's pairs counted (integer atomics), the counts
//                       scanned (gpu/prefix_scan.h), each pair's entries written into its
//                       particles' segments, each segment sorted, so that the order is the pairs'
//   share               each pair's share (and the pair marked as not responded yet)
//   near start          each near pair's geometry at the step's start, the side it keeps
//   proximity           each near pair's push to the thickness, with inelastic contact and Coulomb
//                       friction on its velocities (and on its positions where it was in contact
//                       through the step)
//   impact              each touching pair's closing motion over the step removed at its first
//                       touch, with friction, and its closing velocity
//   gather              each particle's changes, summed in pair order (with a ledger, its state
//                       before the first change kept)
#include "gpu/shaders/shared_text.glsl"
#include "core/closest_points.inc"
#include "collision/self_pair.inc"
#include "gpu/shaders/self_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Start { Real start[]; };  // [particles][3], m
layout(std430, binding = 1) buffer Position { Real position[]; };     // [particles][3], m: the step's end
layout(std430, binding = 2) buffer Velocity { Real velocity[]; };     // [particles][3], m/s
layout(std430, binding = 3) readonly buffer InverseMass { Real inverse_mass[]; };  // [particles], 0 anchored
layout(std430, binding = 4) readonly buffer Triangles { uint triangles[]; };        // [triangles][3]
layout(std430, binding = 5) readonly buffer Edges { uint edges[]; };                // [edges][2]
layout(std430, binding = 6) readonly buffer Pairs { uint pairs[]; };  // [candidates][2] (self_step.h)
layout(std430, binding = 7) readonly buffer List { uint list[]; };    // [listed]: candidate indices, in order
layout(std430, binding = 8) buffer TableStart { uint table_start[]; };  // [particles]: counts, then scanned
layout(std430, binding = 9) buffer TableFill { uint table_fill[]; };    // [particles]: entries written
layout(std430, binding = 10) buffer Entries { uint entries[]; };        // [4 listed]: 4 pair + corner
layout(std430, binding = 11) buffer Geometry { Real geometry[]; };      // [listed][kGeometryReals]
layout(std430, binding = 12) buffer Change { Real change[]; };          // [listed][kChangeReals]
layout(std430, binding = 13) buffer Counters { uint counters[]; };      // [kCounters]
// [0] the thickness, m; [1] the friction coefficient; [2] the step, s.
layout(std430, binding = 14) readonly buffer RespondReal { Real respond_real[]; };
// With a ledger: each particle's state before the passes changed it ([particles][6]: x, v), and
// whether one did (0, the obstacle pass's 1, kMovedBySelf).
layout(std430, binding = 15) buffer Before { Real before[]; };
layout(std430, binding = 16) buffer Moved { uint moved_flag[]; };

layout(push_constant) uniform Constants { RespondPassConstants constants; };

Vec3 load(uint p, bool at_start) {
  return at_start ? Vec3(start[3u * p], start[3u * p + 1u], start[3u * p + 2u])
                  : Vec3(position[3u * p], position[3u * p + 1u], position[3u * p + 2u]);
}
Vec3 velocity_of(uint p) { return Vec3(velocity[3u * p], velocity[3u * p + 1u], velocity[3u * p + 2u]); }

// Listed pair i: its kind (kPair*) and its 4 particles.
int pair_particles(uint i, out uint particle[4]) {
  const uint c = list[i];
  const uint first = pairs[2u * c];
  const uint second = pairs[2u * c + 1u];
  if ((first & kEdgePairBit) == 0u) {
    particle = uint[4](first, triangles[3u * second], triangles[3u * second + 1u], triangles[3u * second + 2u]);
    return kPairPointTriangle;
  }
  const uint e = first & ~kEdgePairBit;
  particle = uint[4](edges[2u * e], edges[2u * e + 1u], edges[2u * second], edges[2u * second + 1u]);
  return kPairEdgeEdge;
}

PairCorners corners_of(uint particle[4], bool at_start) {
  PairCorners corners;
  for (uint k = 0u; k < 4u; ++k) corners.x[k] = load(particle[k], at_start);
  return corners;
}

PairValues stored_weights(uint i) {
  PairValues c;
  for (uint k = 0u; k < 4u; ++k) c.value[k] = geometry[kGeometryReals * i + 3u + k];
  return c;
}
Vec3 stored_normal(uint i) {
  const uint g = kGeometryReals * i;
  return Vec3(geometry[g], geometry[g + 1u], geometry[g + 2u]);
}
void store_geometry(uint i, PairMeasure measure) {
  const uint g = kGeometryReals * i;
  for (uint a = 0u; a < 3u; ++a) geometry[g + a] = measure.normal[a];
  for (uint k = 0u; k < 4u; ++k) geometry[g + 3u + k] = measure.weight[k];
  geometry[g + 7u] = measure.distance;
}

Real effective_of(uint particle[4], PairValues c) {
  PairValues w;
  for (uint k = 0u; k < 4u; ++k) w.value[k] = inverse_mass[particle[k]];
  return effective_inverse_mass(c, w);
}
Vec3 weighted_sum(uint particle[4], PairValues c, bool velocities) {
  Vec3 sum = Vec3(0.0);
  for (uint k = 0u; k < 4u; ++k) sum += c.value[k] * (velocities ? velocity_of(particle[k]) : load(particle[k], false));
  return sum;
}

// Pair i's change this round: the change of q in position and in velocity, with its effective
// inverse mass (none: a zero change).
void store_change(uint i, Vec3 moved, Vec3 sped, Real effective) {
  const uint g = kChangeReals * i;
  for (uint a = 0u; a < 3u; ++a) {
    change[g + a] = moved[a];
    change[g + 3u + a] = sped[a];
  }
  change[g + 6u] = effective;
}

// The velocity change that removes the closing relative velocity along n (inelastic) and, by
// Coulomb friction, at most mu times as much of the sliding; `friction` is the friction's part.
Vec3 closing_velocity_change(Vec3 relative, Vec3 n, Real mu, out Vec3 friction) {
  friction = Vec3(0.0);
  const Real normal_speed = dot(relative, n);  // m/s, negative closing
  if (normal_speed >= Real(0.0)) return Vec3(0.0);
  const Vec3 sliding = relative - normal_speed * n;
  const Real sliding_speed = length(sliding);
  if (mu > Real(0.0) && sliding_speed > Real(0.0)) {
    friction = (-min(mu * -normal_speed, sliding_speed) / sliding_speed) * sliding;
  }
  return -normal_speed * n + friction;
}

// Whether pair i has responded in this stage, and marks it so.
bool responded(uint i) { return geometry[kGeometryReals * i + 8u] != Real(0.0); }
void mark_responded(uint i) { geometry[kGeometryReals * i + 8u] = Real(1.0); }

// A pair pushed apart goes on having its closing velocity removed while its particles' other
// pairs move them, as the CPU's one response per pair removes it whole.
void proximity(uint i) {
  uint particle[4];
  pair_particles(i, particle);
  const Real thickness = respond_real[0];
  const PairValues c = stored_weights(i);
  const Vec3 n = stored_normal(i);
  const Real separation = dot(weighted_sum(particle, c, false), n);
  const Real effective = effective_of(particle, c);
  const bool push = separation < thickness;
  if ((!push && !responded(i)) || effective <= Real(0.0)) {
    store_change(i, Vec3(0.0), Vec3(0.0), Real(0.0));
    return;
  }
  if (push && constants.first_round != 0u) atomicAdd(counters[kCounterPushed], 1u);
  mark_responded(i);
  Vec3 friction;
  const Vec3 sped = closing_velocity_change(weighted_sum(particle, c, true), n, respond_real[1], friction);
  Vec3 moved = push ? (thickness - separation) * n : Vec3(0.0);
  // In contact through the whole step: friction acted all along it (collision/self_pair.inc).
  const Real start_distance = geometry[kGeometryReals * i + 7u];
  if (push && dot(friction, friction) > Real(0.0) && start_distance <= (Real(1.0) + kSustainedSlack) * thickness) {
    moved += (Real(0.5) * respond_real[2]) * friction;
  }
  store_change(i, moved, sped, effective);
}

void impact(uint i) {
  uint particle[4];
  const int kind = pair_particles(i, particle);
  const Real thickness = respond_real[0];
  const PairCorners at_start = corners_of(particle, true);
  const PairCorners at_end = corners_of(particle, false);
  const Real tau = first_touch(kind, at_start, at_end, thickness, measure_pair_corners(kind, at_start).distance);
  store_change(i, Vec3(0.0), Vec3(0.0), Real(0.0));
  if (tau < Real(0.0)) {
    // Its motion no longer touches: its velocities made inelastic at its last touch.
    if (!responded(i)) return;
    const PairValues c = stored_weights(i);
    const Real effective = effective_of(particle, c);
    if (effective > Real(0.0)) {
      Vec3 friction;
      const Vec3 relative = weighted_sum(particle, c, true);
      store_change(i, Vec3(0.0), closing_velocity_change(relative, stored_normal(i), respond_real[1], friction),
                   effective);
    }
    return;
  }
  const PairMeasure measure = measure_pair_corners(kind, interpolate_pair(at_start, at_end, tau));
  store_geometry(i, measure);
  const PairValues c = stored_weights(i);
  const Real effective = effective_of(particle, c);
  if (measure.distance == Real(0.0) || effective <= Real(0.0)) return;
  const Vec3 n = measure.normal;
  // The pair's relative motion over the step, and its part along n (negative: closing).
  Vec3 relative = Vec3(0.0);
  for (uint k = 0u; k < 4u; ++k) relative += c.value[k] * (at_end.x[k] - at_start.x[k]);
  const Real closing = dot(relative, n);
  if (closing >= Real(0.0)) return;
  atomicAdd(counters[kCounterImpacts], 1u);
  mark_responded(i);
  // Remove the closing motion, and by friction at most mu times as much of the sliding.
  const Real mu = respond_real[1];
  Vec3 moved = -closing * n;
  const Vec3 sliding = relative - closing * n;
  const Real sliding_length = length(sliding);
  if (mu > Real(0.0) && sliding_length > Real(0.0)) {
    moved -= (min(mu * -closing, sliding_length) / sliding_length) * sliding;
  }
  Vec3 friction;
  const Vec3 sped = closing_velocity_change(weighted_sum(particle, c, true), n, mu, friction);
  store_change(i, moved, sped, effective);
}

void gather(uint p) {
  const Real w = inverse_mass[p];
  if (w == Real(0.0)) return;
  Vec3 moved = Vec3(0.0);
  Vec3 sped = Vec3(0.0);
  const uint first = table_start[p];
  for (uint e = first; e < first + table_fill[p]; ++e) {
    const uint i = entries[e] / 4u;
    const uint k = entries[e] % 4u;
    const uint g = kChangeReals * i;
    const Real effective = change[g + 6u];
    if (effective <= Real(0.0)) continue;
    const Real factor = change[g + 7u] * geometry[kGeometryReals * i + 3u + k] * w / effective;
    moved += factor * Vec3(change[g], change[g + 1u], change[g + 2u]);
    sped += factor * Vec3(change[g + 3u], change[g + 4u], change[g + 5u]);
  }
  if (moved == Vec3(0.0) && sped == Vec3(0.0)) return;
  if (constants.ledger != 0u && moved_flag[p] == 0u) {
    for (uint a = 0u; a < 3u; ++a) {
      before[6u * p + a] = position[3u * p + a];
      before[6u * p + 3u + a] = velocity[3u * p + a];
    }
    moved_flag[p] = kMovedBySelf;
  }
  for (uint a = 0u; a < 3u; ++a) {
    position[3u * p + a] += moved[a];
    velocity[3u * p + a] += sped[a];
  }
}

void main() {
  const uint k = invocation_index();
  const uint phase = constants.phase;
  const bool per_particle = phase == kRespondSort || phase == kRespondGather;
  if (k >= (per_particle ? constants.particles : constants.pairs)) return;
  if (phase == kRespondCount || phase == kRespondFill) {
    uint particle[4];
    pair_particles(k, particle);
    for (uint corner = 0u; corner < 4u; ++corner) {
      const uint p = particle[corner];
      if (phase == kRespondCount) {
        atomicAdd(table_start[p], 1u);
      } else {
        entries[table_start[p] + atomicAdd(table_fill[p], 1u)] = 4u * k + corner;
      }
    }
  } else if (phase == kRespondSort) {
    // The segment is a particle's few pairs: an insertion sort.
    const uint first = table_start[k];
    const uint last = first + table_fill[k];
    for (uint a = first + 1u; a < last; ++a) {
      const uint entry = entries[a];
      uint b = a;
      while (b > first && entries[b - 1u] > entry) {
        entries[b] = entries[b - 1u];
        --b;
      }
      entries[b] = entry;
    }
  } else if (phase == kRespondShare) {
    uint particle[4];
    pair_particles(k, particle);
    uint most = 1u;
    for (uint corner = 0u; corner < 4u; ++corner) {
      if (inverse_mass[particle[corner]] > Real(0.0)) most = max(most, table_fill[particle[corner]]);
    }
    change[kChangeReals * k + 7u] = Real(1.0) / Real(most);
    geometry[kGeometryReals * k + 8u] = Real(0.0);  // not responded yet
  } else if (phase == kRespondNearStart) {
    uint particle[4];
    const int kind = pair_particles(k, particle);
    store_geometry(k, measure_pair_corners(kind, corners_of(particle, true)));
  } else if (phase == kRespondProximity) {
    proximity(k);
  } else if (phase == kRespondImpact) {
    impact(k);
  } else {
    gather(k);
  }
}
