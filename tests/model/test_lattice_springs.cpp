// The lattice's spring order (model/lattice_springs.inc, shared with the shaders) and its walker:
// the table is the paper's six pairs, the walker visits the springs in the order build_lattice()
// numbers them, and a particle's springs come out as the closed form says.
#include "model/lattice_springs.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "model/cloth_model.h"

namespace clothsim {
namespace {

TEST(LatticeSprings, TheTableIsFourAdjacentPairsThenTwoOpposite) {
  for (std::size_t pair = 0; pair < 4; ++pair) {
    EXPECT_EQ(kRadialArmB[pair], static_cast<int>(pair));
    EXPECT_EQ(kRadialArmC[pair], static_cast<int>((pair + 1) % 4));
    EXPECT_FALSE(radial_pair_is_opposite(pair));
  }
  EXPECT_EQ(kRadialArmB[4], 0);  // east, west
  EXPECT_EQ(kRadialArmC[4], 2);
  EXPECT_EQ(kRadialArmB[5], 1);  // south, north
  EXPECT_EQ(kRadialArmC[5], 3);
  EXPECT_TRUE(radial_pair_is_opposite(4));
  EXPECT_TRUE(radial_pair_is_opposite(5));
  // Every arm is an end of two adjacent springs and one opposite one.
  for (int arm = 0; arm < 4; ++arm) {
    int ends = 0;
    for (std::size_t pair = 0; pair < 6; ++pair) ends += (kRadialArmB[pair] == arm) + (kRadialArmC[pair] == arm);
    EXPECT_EQ(ends, 3) << arm;
  }
}

TEST(LatticeSprings, TheWalkerVisitsTheSpringsInTheModelsOrder) {
  LatticeDef def;
  def.rows = 4;
  def.cols = 5;
  const ClothModel model = build_lattice(def, Environment{}, {});
  std::size_t connectors = 0;
  std::size_t radials = 0;
  const bool complete = for_each_lattice_spring(
      4, 5,
      [&](std::uint32_t e, std::uint32_t p, bool south) {
        EXPECT_EQ(e, connectors++);
        const std::array<std::uint32_t, 2> expected{p, south ? p + 5 : p + 1};
        EXPECT_EQ(model.connector_particles[e], expected) << e;
        return true;
      },
      [&](std::uint32_t r, std::uint32_t p, std::size_t pair) {
        EXPECT_EQ(r, radials++);
        const std::array<std::uint32_t, 3> expected{p, lattice_neighbour(p, kRadialArmB[pair], 5),
                                                    lattice_neighbour(p, kRadialArmC[pair], 5)};
        EXPECT_EQ(model.radial_particles[r], expected) << r;
        EXPECT_EQ(model.radial_kind[r] == RadialKind::opposite, radial_pair_is_opposite(pair)) << r;
        return true;
      });
  EXPECT_TRUE(complete);
  EXPECT_EQ(connectors, model.connector_count());
  EXPECT_EQ(radials, model.radial_count());
}

TEST(LatticeSprings, AnInteriorParticlesSpringsInOrder) {
  // The centre of a 3 x 3 lattice, particle 4: east 5, south 7, west 3, north 1.
  std::vector<std::array<std::uint32_t, 3>> springs;
  for_each_lattice_spring(
      3, 3, [](std::uint32_t, std::uint32_t, bool) { return true; },
      [&](std::uint32_t, std::uint32_t p, std::size_t pair) {
        if (p == 4)
          springs.push_back(
              {p, lattice_neighbour(p, kRadialArmB[pair], 3), lattice_neighbour(p, kRadialArmC[pair], 3)});
        return true;
      });
  const std::vector<std::array<std::uint32_t, 3>> expected{{4, 5, 7}, {4, 7, 3}, {4, 3, 1},
                                                           {4, 1, 5}, {4, 5, 3}, {4, 7, 1}};
  EXPECT_EQ(springs, expected);
  // The walk stops at the first visit that returns false.
  int visits = 0;
  EXPECT_FALSE(for_each_lattice_spring(
      3, 3, [&](std::uint32_t, std::uint32_t, bool) { return ++visits < 3; },
      [](std::uint32_t, std::uint32_t, std::size_t) { return true; }));
  EXPECT_EQ(visits, 3);
}

}  // namespace
}  // namespace clothsim
