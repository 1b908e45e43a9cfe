// Pairs of a particle and a triangle, and of two edges, with a motion each, for the tests of
// self-collision's pair geometry (collision/self_pair.inc): at random and in the degenerate cases
// (a triangle that is a segment, a line or has two corners at one place, parallel edges, an edge
// that is a point), still, translated rigidly, and passing through each other; and the shared text
// as the CPU's self pass compiles it (collision/self_pair.h).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "collision/self_contacts.h"
#include "collision/self_pair.h"
#include "core/vec3.h"
#include "test_support.h"

namespace clothsim::testing {

namespace shared = clothsim::self_pair;

inline constexpr double kPairThickness = 0.05;

struct PairCase {
  SelfPair::Kind kind = SelfPair::Kind::point_triangle;
  std::array<Vec3, 4> start;
  std::array<Vec3, 4> end;
};

inline int kind_of(SelfPair::Kind kind) {
  return kind == SelfPair::Kind::point_triangle ? shared::kPairPointTriangle : shared::kPairEdgeEdge;
}

inline shared::PairCorners corners(const std::array<Vec3, 4>& x) { return {{x[0], x[1], x[2], x[3]}}; }

inline Vec3 random_point(TestRandom& random, double scale) {
  return {random.uniform(-scale, scale), random.uniform(-scale, scale), random.uniform(-scale, scale)};
}

// `count` pairs, alternating the two kinds; their motions: a random one, a rigid translation, or
// one that carries the first side through the second (mirrored through the second side's nearest
// point).
inline std::vector<PairCase> random_pair_cases(int count) {
  TestRandom random(91);
  std::vector<PairCase> cases;
  for (int i = 0; i < count; ++i) {
    PairCase c;
    c.kind = i % 2 == 0 ? SelfPair::Kind::point_triangle : SelfPair::Kind::edge_edge;
    for (Vec3& x : c.start) x = random_point(random, 0.5);
    switch ((i / 2) % 8) {
      case 0: c.start[2] = c.start[1]; break;                                      // two corners at one place
      case 1: c.start[3] = c.start[1] + 0.5 * (c.start[2] - c.start[1]); break;    // a line
      case 2: c.start[1] = c.start[0] + 1e-20 * random_point(random, 1.0); break;  // an edge that is a point
      case 3: c.start[3] = c.start[2] + 2.0 * (c.start[1] - c.start[0]); break;    // parallel edges
      default: break;
    }
    const int motion = i % 3;
    const Vec3 shift = random_point(random, 0.3);
    for (int k = 0; k < 4; ++k) c.end[k] = c.start[k] + (motion == 1 ? shift : random_point(random, 0.3));
    if (motion == 2) {
      const PairGeometry g = measure_pair(c.kind, c.start);
      const int first_side = c.kind == SelfPair::Kind::point_triangle ? 1 : 2;
      for (int k = 0; k < first_side; ++k) c.end[k] = c.start[k] - 2.0 * g.distance * g.normal;
      for (int k = first_side; k < 4; ++k) c.end[k] = c.start[k];
    }
    cases.push_back(c);
  }
  return cases;
}

}  // namespace clothsim::testing
