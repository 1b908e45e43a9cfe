// The self-collision pass from inside (collision/self_contacts.h, collision/box_grid.h): the
// accelerated search against brute force, the pair distances against sampling, and runs with
// self-collision bit-identical across thread counts. The scenes that must never cross are in
// test_self_crossings.cpp, counted by a checker written apart from the solver.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "collision/box_grid.h"
#include "collision/self_contacts.h"
#include "core/closest_points.h"
#include "folded_sheet.h"
#include "folded_strip.h"
#include "model/cloth_model.h"
#include "sheet_crossings.h"
#include "sim/simulation.h"
#include "test_checks.h"

namespace clothsim {
namespace {

Box random_box(std::mt19937& random, double space, double largest) {
  std::uniform_real_distribution<double> where(-space, space);
  std::uniform_real_distribution<double> size(0.0, largest);
  const Vec3 low{where(random), where(random), where(random)};
  return {low, low + Vec3{size(random), size(random), size(random)}};
}

TEST(BoxGrid, FindsTheSamePairsAsBruteForce) {
  std::mt19937 random(7);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Box> stored;
    std::vector<Box> queries;
    for (int i = 0; i < 400; ++i) stored.push_back(random_box(random, 0.6, 0.25));
    // A few boxes far larger than the rest: kept aside, tested against every query.
    if (trial % 2 == 1) {
      for (int i = 0; i < 3; ++i) stored.push_back(random_box(random, 1.0, 3.0));
    }
    for (int i = 0; i < 300; ++i) queries.push_back(random_box(random, 0.7, trial % 3 == 0 ? 0.0 : 0.5));
    BoxGrid grid;
    grid.build(stored);
    std::vector<std::array<std::uint32_t, 2>> found;
    for (std::size_t i = 0; i < queries.size(); ++i) {
      grid.for_each_overlap(queries[i], [&](std::uint32_t j) { found.push_back({static_cast<std::uint32_t>(i), j}); });
    }
    std::sort(found.begin(), found.end());
    const auto expected = overlapping_pairs_brute_force(queries, stored);
    EXPECT_GT(expected.size(), 50u);
    EXPECT_EQ(found, expected) << "trial " << trial << ": each overlapping pair exactly once";

    // The grid joined with itself, in two bucket ranges: every overlapping (i < j) once.
    std::vector<std::array<std::uint32_t, 2>> joined;
    const std::size_t half = grid.bucket_count() / 2;
    const auto add = [&](std::uint32_t i, std::uint32_t j) { joined.push_back({i, j}); };
    grid.for_each_pair(0, half, add);
    grid.for_each_pair(half, grid.bucket_count(), add);
    std::sort(joined.begin(), joined.end());
    std::vector<std::array<std::uint32_t, 2>> self_expected;
    for (const auto& pair : overlapping_pairs_brute_force(stored, stored)) {
      if (pair[0] < pair[1]) self_expected.push_back(pair);
    }
    EXPECT_EQ(joined, self_expected) << "trial " << trial << ": the self-join";
  }
}

// Built over several threads, the grid is the serial one: every query and the self-join visit the
// same boxes in the same order (the order of the candidates, and so of the serial changes,
// depends on it). Enough boxes for several blocks of the build, with some kept aside.
TEST(BoxGrid, IsTheSameForAnyThreadCount) {
  std::mt19937 random(11);
  std::vector<Box> stored;
  for (int i = 0; i < 20'000; ++i) stored.push_back(random_box(random, 2.0, 0.2));
  for (int i = 0; i < 5; ++i) stored.push_back(random_box(random, 2.0, 3.0));
  std::vector<Box> queries;
  for (int i = 0; i < 2'000; ++i) queries.push_back(random_box(random, 2.0, 0.1));
  const auto visits = [&](int threads) {
    BoxGrid grid;
    grid.build(stored, threads);
    std::vector<std::uint32_t> order;
    for (const Box& query : queries) {
      grid.for_each_overlap(query, [&](std::uint32_t j) { order.push_back(j); });
      order.push_back(~0u);
    }
    grid.for_each_pair(0, grid.bucket_count(), [&](std::uint32_t i, std::uint32_t j) {
      order.push_back(i);
      order.push_back(j);
    });
    return order;
  };
  const std::vector<std::uint32_t> serial = visits(1);
  EXPECT_GT(serial.size(), 40'000u);  // pairs to order
  for (int threads : {2, 3, 4}) EXPECT_EQ(visits(threads), serial) << threads << " threads";
}

ClothModel sheet(int rows, int cols, double spacing) {
  LatticeDef def;
  def.rows = rows;
  def.cols = cols;
  def.spacing = spacing;
  def.particle_mass = 0.01;
  def.connector = {50.0, 0.1};
  def.adjacent = {0.01, 0.0};
  def.opposite = {0.01, 0.0};
  return build_lattice(def, Environment{}, {});
}

// Crumpled configurations: the rest lattice folded and shaken at random, moved by a random step.
std::array<std::vector<Vec3>, 2> random_motion(const ClothModel& model, std::mt19937& random, double shake,
                                               double motion) {
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<Vec3> start(model.particle_count());
  std::vector<Vec3> end(model.particle_count());
  for (std::size_t p = 0; p < start.size(); ++p) {
    Vec3 x = model.particle_rest_position[p];
    x = {x.x, 0.2 * std::sin(7.0 * x.x) + 0.2 * std::cos(5.0 * x.z), 0.5 * x.z};  // folds onto itself
    start[p] = x + shake * Vec3{noise(random), noise(random), noise(random)};
    end[p] = start[p] + motion * Vec3{noise(random), noise(random), noise(random)};
  }
  return {start, end};
}

Box brute_box(const std::vector<Vec3>& start, const std::vector<Vec3>& end, std::span<const std::uint32_t> particles,
              double margin) {
  Box box{start[particles[0]], start[particles[0]]};
  for (std::uint32_t p : particles) {
    for (const Vec3& x : {start[p], end[p]}) {
      box.low = {std::min(box.low.x, x.x), std::min(box.low.y, x.y), std::min(box.low.z, x.z)};
      box.high = {std::max(box.high.x, x.x), std::max(box.high.y, x.y), std::max(box.high.z, x.z)};
    }
  }
  return {box.low - Vec3{margin, margin, margin}, box.high + Vec3{margin, margin, margin}};
}

bool shares(std::span<const std::uint32_t> a, std::span<const std::uint32_t> b) {
  for (std::uint32_t p : a) {
    if (std::find(b.begin(), b.end(), p) != b.end()) return true;
  }
  return false;
}

// Every (particle, triangle) and (edge, later edge) pair that shares no particle and whose boxes
// overlap, by visiting all pairs.
std::set<std::array<std::uint32_t, 5>> brute_force_candidates(const SheetElements& elements,
                                                              const std::vector<Vec3>& start,
                                                              const std::vector<Vec3>& end, double margin) {
  std::set<std::array<std::uint32_t, 5>> pairs;
  for (std::uint32_t p = 0; p < start.size(); ++p) {
    const std::array<std::uint32_t, 1> point{p};
    const Box a = brute_box(start, end, point, margin);
    for (const auto& t : elements.triangle) {
      if (shares(point, t) || !overlap(a, brute_box(start, end, t, margin))) continue;
      pairs.insert({0, p, t[0], t[1], t[2]});
    }
  }
  for (std::size_t e = 0; e < elements.edge.size(); ++e) {
    const Box a = brute_box(start, end, elements.edge[e], margin);
    for (std::size_t f = e + 1; f < elements.edge.size(); ++f) {
      if (shares(elements.edge[e], elements.edge[f]) || !overlap(a, brute_box(start, end, elements.edge[f], margin))) {
        continue;
      }
      pairs.insert({1, elements.edge[e][0], elements.edge[e][1], elements.edge[f][0], elements.edge[f][1]});
    }
  }
  return pairs;
}

TEST(SelfContacts, CandidatesMatchBruteForceOnRandomConfigurations) {
  std::mt19937 random(11);
  ClothModel model = sheet(12, 14, 0.05);
  // Torn along a line, so that the torn sheet's triangles and edges are searched too.
  for (std::size_t e = 0; e < model.connector_count(); e += 7) {
    model.connector_live[e] = 0;
    ++model.broken_connector_count;
  }
  for (int trial = 0; trial < 6; ++trial) {
    const auto [start, end] = random_motion(model, random, 0.01 * trial, 0.02);
    const double margin = 0.004 * (trial + 1);
    for (int threads : {1, 2}) {
      SelfContacts contacts;
      contacts.find_candidates(model, start, end, margin, threads);
      std::set<std::array<std::uint32_t, 5>> found;
      std::size_t count = 0;
      for (const SelfPair& pair : contacts.candidates()) {
        const std::uint32_t kind = pair.kind == SelfPair::Kind::point_triangle ? 0 : 1;
        found.insert({kind, pair.particle[0], pair.particle[1], pair.particle[2], pair.particle[3]});
        ++count;
      }
      EXPECT_EQ(count, found.size()) << "no pair twice";
      const auto expected = brute_force_candidates(contacts.elements(), start, end, margin);
      EXPECT_GT(expected.size(), 50u);
      EXPECT_EQ(found, expected) << "trial " << trial << ", " << threads << " threads";
    }
  }
}

TEST(SelfContacts, TornTrianglesAndEdgesLeaveTheSearch) {
  ClothModel model = sheet(3, 3, 1.0);
  SheetElements elements;
  refresh_sheet_elements(model, elements);
  EXPECT_EQ(elements.triangle.size(), 8u);
  EXPECT_EQ(elements.edge.size(), 12u + 4u) << "connectors and diagonals";
  // Breaking the connector (0,0)-(0,1) takes the triangle on its side away (a border connector
  // has one), and the diagonal of that quad stays with the other triangle.
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    const auto [a, b] = model.connector_particles[e];
    if ((a == 0 && b == 1) || (a == 1 && b == 0)) {
      model.connector_live[e] = 0;
      ++model.broken_connector_count;
    }
  }
  refresh_sheet_elements(model, elements);
  EXPECT_EQ(elements.triangle.size(), 7u);
  EXPECT_EQ(elements.edge.size(), 11u + 4u);
}

TEST(SelfContacts, PairDistanceIsTheLeastOverSampledPoints) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> where(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    std::array<Vec3, 4> x;
    for (Vec3& v : x) v = {where(random), where(random), where(random)};
    for (const auto kind : {SelfPair::Kind::point_triangle, SelfPair::Kind::edge_edge}) {
      const PairGeometry geometry = measure_pair(kind, x);
      // The weights give the nearest points: their difference has the reported length.
      Vec3 q;
      for (int k = 0; k < 4; ++k) q += geometry.weight[k] * x[k];
      EXPECT_NEAR(norm(q), geometry.distance, 1e-12);
      // No sampled pair of points is nearer.
      double least = 1e300;
      constexpr int kSamples = 40;
      for (int i = 0; i <= kSamples; ++i) {
        for (int j = 0; i + j <= kSamples; ++j) {
          const double u = double(i) / kSamples;
          const double v = double(j) / kSamples;
          if (kind == SelfPair::Kind::point_triangle) {
            least = std::min(least, norm(x[0] - ((1 - u - v) * x[1] + u * x[2] + v * x[3])));
          } else {
            const double s = double(i) / kSamples;
            for (int k = 0; k <= kSamples; ++k) {
              const double t = double(k) / kSamples;
              least = std::min(least, norm(((1 - s) * x[0] + s * x[1]) - ((1 - t) * x[2] + t * x[3])));
            }
          }
        }
      }
      EXPECT_LE(geometry.distance, least + 1e-12);
      EXPECT_GE(geometry.distance, least - 0.1) << "within the sampling's resolution";
    }
  }
}

// With self-collision on the results must be the same bits for any thread count, and contact
// never adds energy to the falling sheet.
TEST(SelfContacts, RunsAreBitIdenticalAcrossThreadCounts) {
  std::vector<ClothState> results;
  std::vector<ContactStatistics> statistics;
  for (int threads : {1, 2, 3}) {
    Simulation simulation = testing::folded_sheet(IntegratorKind::implicit_euler, 1e-3, threads);
    const double start_energy = simulation.energy().total();
    for (int frame = 1; frame <= 20; ++frame) {
      ASSERT_TRUE(simulation.advance_to(0.01 * frame));
      EXPECT_LE(simulation.energy().total(), start_energy) << "frame " << frame;
    }
    results.push_back(simulation.state());
    statistics.push_back(simulation.contact_statistics());
  }
  EXPECT_GT(statistics[0].self_contact_steps, 0u) << "the sheet touches itself";
  for (std::size_t i = 1; i < results.size(); ++i) {
    EXPECT_EQ(statistics[i].self_contact_steps, statistics[0].self_contact_steps);
    checks::expect_same_bits(results[i], results[0]);
  }
}

// The pass acts on accepted states, so every integrator works with it: the folded sheet lands on
// itself without crossing (the brute-force check of sheet_crossings.h) and without gaining energy.
TEST(SelfContacts, EveryIntegratorKeepsAFoldedSheetUncrossed) {
  for (IntegratorKind kind : all_integrator_kinds()) {
    SCOPED_TRACE(std::string(to_string(kind)));
    Simulation simulation = testing::folded_sheet(kind, kind == IntegratorKind::implicit_euler ? 1e-3 : 2e-4, 1);
    const double start_energy = simulation.energy().total();
    for (int frame = 1; frame <= 15; ++frame) {
      ASSERT_TRUE(simulation.advance_to(0.01 * frame)) << simulation.failure()->message;
      EXPECT_EQ(testing::count_sheet_crossings(simulation.model(), simulation.state().position), 0u)
          << "frame " << frame;
      EXPECT_LE(simulation.energy().total(), start_energy + 1e-9) << "frame " << frame;
    }
    EXPECT_GT(simulation.contact_statistics().self_contact_steps, 0u);
  }
}

// Stage 3 alone stops a particle that passes through the sheet within one step: a 3 x 6 strip
// folded in half over itself, one particle of the top layer moved 10 cm down through the bottom
// layer in the step. At neither end of the step is it within the thickness of anything (stage 2
// sees nothing), so only the continuous test finds it; without it the step ends crossed.
TEST(SelfContacts, ImpactStageStopsAParticlePassingThroughWithinAStep) {
  testing::FoldedStrip strip = testing::folded_strip();
  const ClothModel& model = strip.model;
  ClothState& state = strip.state;
  const std::size_t moved = strip.moved;
  ASSERT_EQ(testing::count_sheet_crossings(model, strip.start), 0u) << "the fold starts uncrossed";
  ASSERT_GT(testing::count_sheet_crossings(model, state.position), 0u) << "the step as taken crosses";

  SelfContacts contacts;
  const SelfContactCounts counts = contacts.apply(model, state, strip.start, 0.01, kAllForceTerms, 1);
  EXPECT_GT(counts.impacts, 0u);
  EXPECT_EQ(counts.unresolved, 0u);
  EXPECT_EQ(testing::count_sheet_crossings(model, state.position), 0u);
  EXPECT_GT(state.position[moved].y, 0.0) << "it stays above the bottom layer";
}

}  // namespace
}  // namespace clothsim
