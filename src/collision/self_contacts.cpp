#include "collision/self_contacts.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>

#include "collision/self_pair.h"
#include "core/parallel.h"

namespace clothsim {
namespace {

// The pair geometry the device computes as well (collision/self_pair.inc).
namespace shared = self_pair;

// Stage 1 runs its queries in blocks of this many elements, each block filling its own list; the
// lists are joined in block order, so the candidates' order does not depend on the threads.
constexpr std::size_t kQueryBlock = 512;
constexpr std::size_t kBucketBlock = 4096;
// Stage 1 keeps its candidates while no particle moves further than a reach from where they were
// found: at least this many thicknesses, and a few times the largest motion of the step they
// were found in (see refresh_candidates). A falling sheet finds them again every few steps, a
// sheet at rest almost never.
constexpr double kLeastReach = 1.0;
// Stage 3 selects its active pairs again only when a particle moved more than this many
// thicknesses since they were selected (less than the h / 2 they were selected with, less the
// touching distance h / 10).
constexpr double kReselect = 0.2;
constexpr double kLeastSteps = 2.0;
constexpr double kMostSteps = 8.0;
// Gauss-Seidel sweeps of stage 2 over the pairs found near.
constexpr int kProximitySweeps = 4;
// Stage 3: a pair touches when its distance falls below a fraction of the thickness
// (collision/self_pair.inc, first_touch), for at most this many rounds of responses.
constexpr int kImpactRounds = 8;
// Stage 4 merges and moves zones at most this many times.
constexpr int kZoneRounds = 32;

// The pair's 4 corners at positions x.
shared::PairCorners gather(const SelfPair& pair, std::span<const Vec3> x) {
  return {{x[pair.particle[0]], x[pair.particle[1]], x[pair.particle[2]], x[pair.particle[3]]}};
}

Vec3 weighted_sum(const std::array<double, 4>& weight, const SelfPair& pair, std::span<const Vec3> x) {
  Vec3 sum{0.0, 0.0, 0.0};
  for (int k = 0; k < 4; ++k) sum += weight[k] * x[pair.particle[k]];
  return sum;
}

PairGeometry geometry_of(const shared::PairMeasure& measure) {
  const auto& w = measure.weight;
  return {measure.distance, measure.normal, {w[0], w[1], w[2], w[3]}};
}

int shared_kind(SelfPair::Kind kind) {
  return kind == SelfPair::Kind::point_triangle ? shared::kPairPointTriangle : shared::kPairEdgeEdge;
}

// The pair's distance, normal and weights at positions x.
shared::PairMeasure measure(const SelfPair& pair, std::span<const Vec3> x) {
  return shared::measure_pair_corners(shared_kind(pair.kind), gather(pair, x));
}

// The first tau in [0, 1] at which the pair's distance along start -> end comes within touching
// distance, or a negative value if it never does (stage 3; collision/self_pair.inc);
// `start_distance` is its distance at start.
double first_touch(const SelfPair& pair, std::span<const Vec3> start, std::span<const Vec3> end, double thickness,
                   double start_distance) {
  return shared::first_touch(shared_kind(pair.kind), gather(pair, start), gather(pair, end), thickness, start_distance);
}

double first_touch(const SelfPair& pair, std::span<const Vec3> start, std::span<const Vec3> end, double thickness) {
  return first_touch(pair, start, end, thickness, measure(pair, start).distance);
}

// Moves the pair's particles so that q changes by `change` (a vector along which the particles
// move in proportion to c_k w_k), each particle's share added to `target`, scaled by `scale`.
void spread(const SelfPair& pair, const std::array<double, 4>& weight, std::span<const double> inverse_mass,
            double effective, const Vec3& change, double scale, std::span<Vec3> target) {
  for (int k = 0; k < 4; ++k) {
    const std::uint32_t p = pair.particle[k];
    target[p] += (scale * weight[k] * inverse_mass[p] / effective) * change;
  }
}

// K = sum_k c_k^2 w_k, at least a share of the largest w_k (collision/self_pair.inc).
double effective_inverse_mass(const SelfPair& pair, const std::array<double, 4>& weight,
                              std::span<const double> inverse_mass) {
  shared::PairValues c{};
  shared::PairValues w{};
  for (int k = 0; k < 4; ++k) {
    c.value[k] = weight[k];
    w.value[k] = inverse_mass[pair.particle[k]];
  }
  return shared::effective_inverse_mass(c, w);
}

// Removes the pair's closing relative velocity along n (inelastic) and, by Coulomb friction, at
// most mu times as much of its sliding velocity. Returns the change friction made to the
// relative velocity (zero when not closing).
Vec3 remove_closing_velocity(const SelfPair& pair, const std::array<double, 4>& weight,
                             std::span<const double> inverse_mass, double effective, const Vec3& n, double mu,
                             std::span<Vec3> velocity) {
  const Vec3 relative = weighted_sum(weight, pair, velocity);
  const double normal_speed = dot(relative, n);  // m/s, negative closing
  if (normal_speed >= 0.0) return {};
  spread(pair, weight, inverse_mass, effective, n, -normal_speed, velocity);
  const Vec3 sliding = relative - normal_speed * n;
  const double sliding_speed = norm(sliding);
  if (mu <= 0.0 || sliding_speed == 0.0) return {};
  const Vec3 friction_change = (-std::min(mu * -normal_speed, sliding_speed) / sliding_speed) * sliding;
  spread(pair, weight, inverse_mass, effective, friction_change, 1.0, velocity);
  return friction_change;
}

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t p) {
  while (parent[p] != p) {
    parent[p] = parent[parent[p]];
    p = parent[p];
  }
  return p;
}

// Joins the sets of a and b; the smaller index is the root, so the zones do not depend on order.
void join(std::vector<std::uint32_t>& parent, std::uint32_t a, std::uint32_t b) {
  a = find_root(parent, a);
  b = find_root(parent, b);
  if (a == b) return;
  if (a < b) {
    parent[b] = a;
  } else {
    parent[a] = b;
  }
}

bool shares_particle(const std::array<std::uint32_t, 2>& e, const std::array<std::uint32_t, 2>& f) {
  return e[0] == f[0] || e[0] == f[1] || e[1] == f[0] || e[1] == f[1];
}

}  // namespace

PairGeometry measure_pair(SelfPair::Kind kind, const std::array<Vec3, 4>& x) {
  return geometry_of(shared::measure_pair_corners(shared_kind(kind), {{x[0], x[1], x[2], x[3]}}));
}

void SelfContacts::motion_boxes(std::span<const Vec3> start, std::span<const Vec3> end, double margin, int threads) {
  const auto& triangles = elements_.triangle;
  const auto& edges = elements_.edge;
  point_box_.resize(end.size());
  triangle_box_.resize(triangles.size());
  edge_box_.resize(edges.size());
  // Each particle's box once; an element's is the union of its particles' (a particle belongs to
  // up to 6 triangles and 6 edges), then grown. The particles' boxes are grown last.
  parallel_for(end.size(), threads, [&](std::size_t p) {
    point_box_[p] = {{std::min(start[p].x, end[p].x), std::min(start[p].y, end[p].y), std::min(start[p].z, end[p].z)},
                     {std::max(start[p].x, end[p].x), std::max(start[p].y, end[p].y), std::max(start[p].z, end[p].z)}};
  });
  const Vec3 grow{margin, margin, margin};
  const auto element_box = [&](std::span<const std::uint32_t> particles) {
    Box box = point_box_[particles[0]];
    for (std::uint32_t p : particles.subspan(1)) {
      const Box& other = point_box_[p];
      box.low = {std::min(box.low.x, other.low.x), std::min(box.low.y, other.low.y), std::min(box.low.z, other.low.z)};
      box.high = {std::max(box.high.x, other.high.x), std::max(box.high.y, other.high.y),
                  std::max(box.high.z, other.high.z)};
    }
    return Box{box.low - grow, box.high + grow};
  };
  parallel_for(triangles.size(), threads, [&](std::size_t t) { triangle_box_[t] = element_box(triangles[t]); });
  parallel_for(edges.size(), threads, [&](std::size_t e) { edge_box_[e] = element_box(edges[e]); });
  parallel_for(end.size(), threads, [&](std::size_t p) {
    point_box_[p] = {point_box_[p].low - grow, point_box_[p].high + grow};
  });
}

void SelfContacts::find_candidates(const ClothModel& model, std::span<const Vec3> start, std::span<const Vec3> end,
                                   double margin, int threads) {
  search(model, start, end, margin, threads);
  join_blocks(threads);
}

void SelfContacts::search(const ClothModel& model, std::span<const Vec3> start, std::span<const Vec3> end,
                          double margin, int threads) {
  refresh_sheet_elements(model, elements_);
  const std::size_t particles = model.particle_count();
  const auto& triangles = elements_.triangle;
  const auto& edges = elements_.edge;
  motion_boxes(start, end, margin, threads);
  triangle_grid_.build(triangle_box_, threads);
  edge_grid_.build(edge_box_, threads);

  // Queries: the particles against the triangles; then the edge grid joined with itself, in
  // blocks of buckets (each pair of edges met once per cell, where querying every edge would meet
  // it twice).
  const std::size_t point_blocks = (particles + kQueryBlock - 1) / kQueryBlock;
  const std::size_t buckets = edge_grid_.bucket_count();
  const std::size_t edge_blocks = (buckets + kBucketBlock - 1) / kBucketBlock;
  block_pairs_.resize(point_blocks + edge_blocks);
  // A block of queries costs several times a block of buckets: handed out as threads come free.
  parallel_for_dynamic(point_blocks + edge_blocks, threads, [&](std::size_t block) {
    std::vector<SelfPair>& out = block_pairs_[block];
    out.clear();
    if (block < point_blocks) {
      const std::size_t end_index = std::min(particles, (block + 1) * kQueryBlock);
      for (std::size_t p = block * kQueryBlock; p < end_index; ++p) {
        const auto point = static_cast<std::uint32_t>(p);
        triangle_grid_.for_each_overlap(point_box_[p], [&](std::uint32_t t) {
          const auto& corner = triangles[t];
          if (corner[0] == point || corner[1] == point || corner[2] == point) return;
          out.push_back({{point, corner[0], corner[1], corner[2]}, {point, t}, SelfPair::Kind::point_triangle});
        });
      }
    } else {
      const std::size_t first = (block - point_blocks) * kBucketBlock;
      edge_grid_.for_each_pair(first, std::min(buckets, first + kBucketBlock), [&](std::uint32_t e, std::uint32_t f) {
        if (shares_particle(edges[e], edges[f])) return;
        out.push_back({{edges[e][0], edges[e][1], edges[f][0], edges[f][1]}, {e, f}, SelfPair::Kind::edge_edge});
      });
    }
  });
  found_at_.assign(end.begin(), end.end());
}

void SelfContacts::join_blocks(int threads) {
  const std::size_t blocks = block_pairs_.size();
  block_start_.assign(blocks + 1, 0);
  for (std::size_t b = 0; b < blocks; ++b) block_start_[b + 1] = block_start_[b] + block_pairs_[b].size();
  candidates_.resize(block_start_[blocks]);
  parallel_for(blocks, threads, [&](std::size_t b) {
    std::copy(block_pairs_[b].begin(), block_pairs_[b].end(),
              candidates_.begin() + static_cast<std::ptrdiff_t>(block_start_[b]));
  });
}

void SelfContacts::refresh_candidates(const ClothModel& model, std::span<const Vec3> start, std::span<const Vec3> end,
                                      int threads) {
  const double thickness = model.collision.thickness;
  const bool same_sheet = found_at_.size() == end.size() && found_thickness_ == thickness &&
                          elements_.built_particles == model.particle_count() &&
                          elements_.built_broken == model.broken_connector_count;
  bool keep = same_sheet;
  if (same_sheet) {
    // The boxes held the end positions x_f they were found at, grown by the thickness plus the
    // reach. While every position of the motion start -> end stays within the reach of x_f, the
    // motion's boxes grown by the thickness lie inside them, so every pair that can come within
    // the thickness is among the candidates.
    const auto farthest = [&](std::size_t p) {
      return std::max(squared_norm(end[p] - found_at_[p]), squared_norm(start[p] - found_at_[p]));
    };
    const double moved = parallel_max(end.size(), threads, farthest, 0.0);
    keep = std::sqrt(moved) <= found_reach_;
  }
  if (keep && selection_current_) {
    // The active pairs were selected with boxes grown by h / 2 for a touching distance of at
    // most h / 10; end positions moved less than the difference since still leave every pair
    // that can touch among them (the start positions do not change within a step).
    const double changed = parallel_max(
        end.size(), threads, [&](std::size_t p) { return squared_norm(end[p] - selected_at_[p]); }, 0.0);
    if (std::sqrt(changed) <= kReselect * thickness) return;
  }
  if (!keep) {
    const double moved = std::sqrt(parallel_max(
        end.size(), threads, [&](std::size_t p) { return squared_norm(end[p] - start[p]); }, 0.0));
    const double reach = candidate_reach(moved, same_sheet ? found_reach_ : 0.0, thickness, model.spacing);
    search(model, start, end, thickness + reach, threads);
    prune_blocks(end, prune_distance(moved, reach, thickness), threads);
    join_blocks(threads);
    found_thickness_ = thickness;
    found_reach_ = reach;
  }
  select_active(start, end, thickness, threads);
}

double SelfContacts::candidate_reach(double moved, double last_reach, double thickness, double spacing) {
  // At least the thickness and kLeastSteps steps of this step's motion; up to kMostSteps steps of
  // it (or half the last reach, so that one short step of an adaptive integrator does not make the
  // next few find them again every step) as long as pruning still drops the lattice's
  // neighbouring cells (L / sqrt(2) apart). A larger reach finds the candidates less often but
  // keeps more of them, which every step tests.
  const double neighbours = 0.5 * (std::numbers::sqrt2 / 2.0 * spacing - thickness);
  return std::max({kLeastReach * thickness, kLeastSteps * moved,
                   std::min(std::max(kMostSteps * moved, 0.5 * last_reach), neighbours)});
}

double SelfContacts::prune_distance(double moved, double reach, double thickness) {
  // This step's motion is within `moved` of the end positions, later ones within the reach.
  return thickness + 2.0 * std::max(reach, moved);
}

void SelfContacts::prune_blocks(std::span<const Vec3> x, double reach, int threads) {
  // Until the candidates are found again no particle moves further than (reach - thickness) / 2
  // from x, so a pair's distance changes by less than reach - thickness: a pair at least `reach`
  // apart at x stays out of the thickness. Most candidates from the boxes are such pairs (on a
  // lattice, the particles and triangles of neighbouring cells, L / sqrt(2) apart or more), and
  // the steps test only the rest.
  // Each block in place, in its order: the kept pairs are those of the serial loop, in its order.
  parallel_for_dynamic(block_pairs_.size(), threads, [&](std::size_t b) {
    std::vector<SelfPair>& pairs = block_pairs_[b];
    std::size_t kept = 0;
    for (const SelfPair& pair : pairs) {
      if (measure(pair, x).distance < reach) pairs[kept++] = pair;
    }
    pairs.resize(kept);
  });
}

void SelfContacts::select_active(std::span<const Vec3> start, std::span<const Vec3> end, double thickness,
                                 int threads) {
  // Each element's box over the motion, once, then one overlap test per candidate.
  motion_boxes(start, end, 0.5 * thickness, threads);
  active_flag_.resize(candidates_.size());
  parallel_for(candidates_.size(), threads, [&](std::size_t i) {
    const SelfPair& pair = candidates_[i];
    const bool point = pair.kind == SelfPair::Kind::point_triangle;
    const Box& first = point ? point_box_[pair.element[0]] : edge_box_[pair.element[0]];
    const Box& second = point ? triangle_box_[pair.element[1]] : edge_box_[pair.element[1]];
    active_flag_[i] = overlap(first, second) ? 1 : 0;
  });
  parallel_select(
      candidates_.size(), threads, [&](std::size_t i) { return active_flag_[i] != 0; }, active_);
  // Their distances at the step's start, which stages 2 and 3 read every round.
  start_distance_.resize(active_.size());
  parallel_for(active_.size(), threads, [&](std::size_t k) {
    const SelfPair& pair = candidates_[active_[k]];
    start_distance_[k] = measure(pair, start).distance;
  });
  selected_at_.assign(end.begin(), end.end());
  selection_current_ = true;
}

void SelfContacts::detect_proximity(std::span<const Vec3> start, std::span<const Vec3> end, double thickness,
                                    int threads) {
  near_.resize(active_.size());
  // Near: within the thickness at the start or the end. Nearest points that coincide at the start
  // have no side to keep (a crossing in the making, which stage 3 stops).
  parallel_for(active_.size(), threads, [&](std::size_t k) {
    const SelfPair& pair = candidates_[active_[k]];
    const bool within = start_distance_[k] < thickness || measure(pair, end).distance < thickness;
    near_[k] = within && start_distance_[k] != 0.0 ? 1 : 0;
  });
  select_flagged(near_, threads);
  near_geometry_.resize(list_.size());
  parallel_for(list_.size(), threads, [&](std::size_t i) {
    const SelfPair& pair = candidates_[list_[i]];
    near_geometry_[i] = geometry_of(measure(pair, start));
  });
}

void SelfContacts::select_flagged(std::span<const std::uint8_t> flag, int threads) {
  parallel_select(
      active_.size(), threads, [&](std::size_t k) { return flag[k] != 0; }, list_);
  parallel_for(list_.size(), threads, [&](std::size_t i) { list_[i] = active_[list_[i]]; });
}

std::size_t SelfContacts::resolve_proximity(const ClothModel& model, ClothState& state, double step) {
  const double thickness = model.collision.thickness;
  const double mu = model.collision.friction;
  std::size_t pushed = 0;
  for (int sweep = 0; sweep < kProximitySweeps; ++sweep) {
    std::size_t pushed_this_sweep = 0;
    for (std::size_t k = 0; k < list_.size(); ++k) {
      const SelfPair& pair = candidates_[list_[k]];
      // The nearest points at the step's start and the direction between them: the side each
      // part of the pair is on, which the end state must keep, at least the thickness apart.
      const PairGeometry& start = near_geometry_[k];
      const Vec3& n = start.normal;
      const double separation = dot(weighted_sum(start.weight, pair, state.position), n);
      if (separation >= thickness) continue;
      const double effective = effective_inverse_mass(pair, start.weight, inverse_mass_);
      if (effective <= 0.0) continue;
      ++pushed_this_sweep;
      spread(pair, start.weight, inverse_mass_, effective, n, thickness - separation, state.position);

      // Velocities: inelastic along n, Coulomb across it.
      const Vec3 friction_change =
          remove_closing_velocity(pair, start.weight, inverse_mass_, effective, n, mu, state.velocity);
      // In contact through the whole step: friction acted all along it (obstacle pass, step 4).
      if (squared_norm(friction_change) > 0.0 && start.distance <= (1.0 + shared::kSustainedSlack) * thickness) {
        spread(pair, start.weight, inverse_mass_, effective, friction_change, 0.5 * step, state.position);
      }
    }
    if (sweep == 0) pushed = pushed_this_sweep;
    if (pushed_this_sweep == 0) break;
  }
  return pushed;
}

std::size_t SelfContacts::detect_impacts(std::span<const Vec3> start, std::span<const Vec3> end, double thickness,
                                         int threads) {
  touching_.resize(active_.size());
  parallel_for(active_.size(), threads, [&](std::size_t k) {
    touching_[k] = first_touch(candidates_[active_[k]], start, end, thickness, start_distance_[k]) >= 0.0 ? 1 : 0;
  });
  select_flagged(touching_, threads);
  return list_.size();
}

bool SelfContacts::resolve_impacts(const ClothModel& model, ClothState& state, std::span<const Vec3> start,
                                   SelfContactCounts& counts, int threads) {
  const double thickness = model.collision.thickness;
  const double mu = model.collision.friction;
  for (int round = 0; round < kImpactRounds; ++round) {
    refresh_candidates(model, start, state.position, threads);
    if (detect_impacts(start, state.position, thickness, threads) == 0) return true;
    for (std::uint32_t i : list_) {
      const SelfPair& pair = candidates_[i];
      // Earlier responses in this round may have changed this pair's motion.
      const double tau = first_touch(pair, start, state.position, thickness);
      if (tau < 0.0) continue;
      const PairGeometry geometry = geometry_of(shared::measure_pair_corners(
          shared_kind(pair.kind), shared::interpolate_pair(gather(pair, start), gather(pair, state.position), tau)));
      const double effective = effective_inverse_mass(pair, geometry.weight, inverse_mass_);
      if (geometry.distance == 0.0 || effective <= 0.0) continue;
      const Vec3& n = geometry.normal;
      // The pair's relative motion over the step, and its part along n (negative: closing).
      Vec3 relative{0.0, 0.0, 0.0};
      for (int k = 0; k < 4; ++k) {
        const std::uint32_t p = pair.particle[k];
        relative += geometry.weight[k] * (state.position[p] - start[p]);
      }
      const double closing = dot(relative, n);
      if (closing >= 0.0) continue;
      ++counts.impacts;
      // Remove the closing motion (the pair keeps its normal separation from the step's start),
      // and by friction at most mu times as much of the sliding.
      Vec3 change = -closing * n;
      const Vec3 sliding = relative - closing * n;
      const double sliding_length = norm(sliding);
      if (mu > 0.0 && sliding_length > 0.0) {
        change -= (std::min(mu * -closing, sliding_length) / sliding_length) * sliding;
      }
      spread(pair, geometry.weight, inverse_mass_, effective, change, 1.0, state.position);
      // The end velocities: inelastic along n. Not the position change over the step: the motion
      // x1 - x0 includes the obstacle pass's projections, which are no velocity, and over a short
      // step would make a large one.
      remove_closing_velocity(pair, geometry.weight, inverse_mass_, effective, n, mu, state.velocity);
    }
  }
  refresh_candidates(model, start, state.position, threads);
  return detect_impacts(start, state.position, thickness, threads) == 0;
}

void SelfContacts::move_zones(const ClothModel& model, ClothState& state, std::span<const Vec3> start,
                              SelfContactCounts& counts, int threads) {
  const std::size_t n = model.particle_count();
  const double thickness = model.collision.thickness;
  zone_parent_.resize(n);
  for (std::size_t p = 0; p < n; ++p) zone_parent_[p] = static_cast<std::uint32_t>(p);
  std::vector<std::uint8_t>& in_zone = changed_;  // reused: the ledger's flags are set after
  in_zone.assign(n, 0);
  // Per root: mass, momentum and motion sums, and the anchor a zone follows.
  struct ZoneSum {
    double mass = 0.0;
    Vec3 momentum;
    Vec3 motion;  // mass-weighted
    std::int64_t anchor = -1;
  };
  std::vector<ZoneSum> sum(n);
  for (int round = 0; round < kZoneRounds; ++round) {
    for (std::uint32_t i : list_) {
      const SelfPair& pair = candidates_[i];
      for (int k = 0; k < 4; ++k) {
        in_zone[pair.particle[k]] = 1;
        join(zone_parent_, pair.particle[0], pair.particle[k]);
      }
    }
    for (std::size_t p = 0; p < n; ++p) sum[p] = ZoneSum{};
    for (std::size_t p = 0; p < n; ++p) {
      if (in_zone[p] == 0) continue;
      ZoneSum& zone = sum[find_root(zone_parent_, static_cast<std::uint32_t>(p))];
      const double mass = model.particle_mass[p];
      zone.mass += mass;
      zone.momentum += mass * state.velocity[p];
      zone.motion += mass * (state.position[p] - start[p]);
      if (model.is_anchored(p) && zone.anchor < 0) zone.anchor = static_cast<std::int64_t>(p);
    }
    std::size_t zones = 0;
    for (std::size_t p = 0; p < n; ++p) {
      if (in_zone[p] == 0) continue;
      const std::uint32_t root = find_root(zone_parent_, static_cast<std::uint32_t>(p));
      if (root == p) ++zones;
      if (model.is_anchored(p)) continue;
      const ZoneSum& zone = sum[root];
      if (zone.anchor >= 0) {
        const auto a = static_cast<std::size_t>(zone.anchor);
        state.position[p] = start[p] + (state.position[a] - start[a]);
        state.velocity[p] = state.velocity[a];
      } else {
        state.position[p] = start[p] + zone.motion / zone.mass;
        state.velocity[p] = zone.momentum / zone.mass;
      }
    }
    counts.zones = zones;
    refresh_candidates(model, start, state.position, threads);
    if (detect_impacts(start, state.position, thickness, threads) == 0) return;
  }
  counts.unresolved = list_.size();
}

SelfContactCounts SelfContacts::apply(const ClothModel& model, ClothState& state, std::span<const Vec3> start,
                                      double step, ForceTerms terms, int threads) {
  SelfContactCounts counts;
  if (!model.collision.self) return counts;
  const std::size_t n = model.particle_count();
  const double thickness = model.collision.thickness;
  selection_current_ = false;  // a new step: new start positions
  before_position_.assign(state.position.begin(), state.position.end());
  before_velocity_.assign(state.velocity.begin(), state.velocity.end());
  inverse_mass_.assign(model.particle_inverse_mass.begin(), model.particle_inverse_mass.end());

  refresh_candidates(model, start, state.position, threads);
  detect_proximity(start, state.position, thickness, threads);
  counts.contacts = resolve_proximity(model, state, step);
  if (!resolve_impacts(model, state, start, counts, threads)) move_zones(model, state, start, counts, threads);

  // Bookkeeping: the particles whose position or velocity the pass changed.
  changed_.resize(n);
  parallel_for(n, threads, [&](std::size_t p) {
    changed_[p] = state.position[p] == before_position_[p] && state.velocity[p] == before_velocity_[p] ? 0 : 1;
  });
  energy_.collect(model, changed_, threads);
  if (energy_.particles().empty()) return counts;
  const double before = energy_.energy(model, before_position_, before_velocity_, terms, threads);
  const double after = energy_.energy(model, state.position, state.velocity, terms, threads);
  counts.work = after - before;
  state.contact_work += counts.work;
  return counts;
}

std::size_t SelfContacts::bytes_for(const LatticeCounts& counts) {
  const std::size_t n = counts.particles;
  const auto [triangles, edges] = sheet_element_counts(counts);
  std::size_t bytes = triangles * sizeof(elements_.triangle[0]) + edges * sizeof(elements_.edge[0]);
  bytes += (n + triangles + edges) * sizeof(Box);
  // Each grid: a low cell and a cell count per box, entries for the cells each box spans, two bucket arrays of
  // at least twice the entries (BoxGrid::build).
  for (const std::size_t boxes : {triangles, edges}) {
    const auto entries = static_cast<std::size_t>(kGridEntriesPerBox * static_cast<double>(boxes));
    bytes += boxes * (3 * sizeof(std::int64_t) + sizeof(std::uint32_t)) +
             entries * (3 * sizeof(std::int64_t) + sizeof(std::uint64_t)) +
             2 * std::bit_ceil(std::max<std::size_t>(2 * entries, 16)) * sizeof(std::uint32_t);
  }
  bytes += n * (4 * sizeof(Vec3) + sizeof(double) + sizeof(std::uint32_t) + 2 * sizeof(std::uint8_t));
  // Candidates: kept in their blocks and in one list, with flags and the active ones' indices and
  // start distances.
  const auto pairs = static_cast<std::size_t>(kCandidatesPerParticle * static_cast<double>(n));
  bytes += pairs * (2 * sizeof(SelfPair) + 3 * sizeof(std::uint8_t) + 2 * sizeof(std::uint32_t) + sizeof(double));
  return bytes + ContactEnergy::bytes_for(counts);
}

std::size_t SelfContacts::bytes() const {
  std::size_t bytes = triangle_grid_.bytes() + edge_grid_.bytes() + energy_.bytes();
  bytes += (point_box_.capacity() + triangle_box_.capacity() + edge_box_.capacity()) * sizeof(Box);
  for (const auto& block : block_pairs_) bytes += block.capacity() * sizeof(SelfPair);
  bytes += candidates_.capacity() * sizeof(SelfPair);
  bytes += (found_at_.capacity() + before_position_.capacity() + before_velocity_.capacity()) * sizeof(Vec3);
  bytes += (inverse_mass_.capacity() + start_distance_.capacity()) * sizeof(double);
  bytes += near_.capacity() + touching_.capacity() + changed_.capacity();
  bytes += (list_.capacity() + zone_parent_.capacity()) * sizeof(std::uint32_t);
  bytes += block_start_.capacity() * sizeof(std::size_t);
  bytes += (elements_.triangle.capacity() * 3 + elements_.edge.capacity() * 2) * sizeof(std::uint32_t);
  return bytes;
}

}  // namespace clothsim
