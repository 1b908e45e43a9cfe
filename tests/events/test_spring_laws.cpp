// The event laws of events/spring_laws.inc, the text the CPU's event stage and the device's event
// passes both compile, against their closed forms (DESIGN.md section 3): tearing at the break
// strain, the return mapping with linear hardening, and the crease law with its clamp to [0, pi].
// tests/gpu/test_shared_laws.cpp holds the shaders' to the same values.
#include "events/spring_laws.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace clothsim {
namespace {

TEST(SpringLaws, AConnectorBreaksPastItsBreakStrain) {
  EXPECT_FALSE(spring_laws::connector_breaks(1.1, 1.0, 0.2));
  EXPECT_TRUE(spring_laws::connector_breaks(1.3, 1.0, 0.2));
  EXPECT_FALSE(spring_laws::connector_breaks(0.5, 1.0, 0.2));  // compression never tears
  EXPECT_FALSE(spring_laws::connector_breaks(2.0, 1.0, 1.0));  // exactly at the threshold: intact
}

TEST(SpringLaws, TheReturnMappingLeavesTheYieldStrain) {
  // Pulled to strain 0.1 with yield 0.02 and no hardening: the rest length becomes l / 1.02, so
  // that the elastic strain is the yield strain.
  const spring_laws::ReturnMapping pulled = spring_laws::return_mapping(1.1, 1.0, 0.02, 0.0);
  EXPECT_TRUE(pulled.yields);
  EXPECT_DOUBLE_EQ(pulled.rest_length, 1.1 / 1.02);
  EXPECT_NEAR(1.1 / pulled.rest_length - 1.0, 0.02, 1e-15);
  EXPECT_EQ(pulled.yield_strain, 0.02);
  // Released, it keeps (1 + S) / (1 + y) - 1 of permanent strain (DESIGN.md).
  EXPECT_NEAR(pulled.rest_length / 1.0 - 1.0, (1.0 + 0.1) / (1.0 + 0.02) - 1.0, 1e-15);
  // Compressed to strain -0.1: the rest length becomes l / (1 - y).
  const spring_laws::ReturnMapping pushed = spring_laws::return_mapping(0.9, 1.0, 0.02, 0.0);
  EXPECT_TRUE(pushed.yields);
  EXPECT_DOUBLE_EQ(pushed.rest_length, 0.9 / 0.98);
}

TEST(SpringLaws, HardeningGrowsTheYieldByThePlasticIncrement) {
  // Plastic increment |eps| - y = 0.08; hardening 0.5 grows the yield by 0.04.
  const spring_laws::ReturnMapping mapping = spring_laws::return_mapping(1.1, 1.0, 0.02, 0.5);
  EXPECT_TRUE(mapping.yields);
  EXPECT_NEAR(mapping.yield_strain, 0.02 + 0.5 * (0.1 - 0.02), 1e-15);
  EXPECT_DOUBLE_EQ(mapping.rest_length, 1.1 / 1.02);  // the mapping uses the yield before it grows
}

TEST(SpringLaws, NoMappingWithinTheYieldOrToANegativeRestLength) {
  const spring_laws::ReturnMapping within = spring_laws::return_mapping(1.01, 1.0, 0.02, 0.5);
  EXPECT_FALSE(within.yields);
  EXPECT_EQ(within.rest_length, 1.0);
  EXPECT_EQ(within.yield_strain, 0.02);
  EXPECT_FALSE(spring_laws::connector_yields(1.01, 1.0, 0.02));
  EXPECT_TRUE(spring_laws::connector_yields(1.03, 1.0, 0.02));
  EXPECT_TRUE(spring_laws::connector_yields(0.97, 1.0, 0.02));
  // Compression with a yield strain of 1 or more would need a rest length l / (1 - y) <= 0.
  const spring_laws::ReturnMapping refused = spring_laws::return_mapping(0.1, 1.0, 1.5, 0.0);
  EXPECT_FALSE(refused.yields);
  EXPECT_EQ(refused.rest_length, 1.0);
}

TEST(SpringLaws, ACreaseMovesTheRestAngleToTheYieldAngleAndStaysInRange) {
  constexpr double pi = std::numbers::pi;
  // Bent 0.5 rad past a rest angle of pi/2 with yield 0.1: the rest angle follows to 0.1 behind.
  EXPECT_DOUBLE_EQ(spring_laws::creased_rest_angle(pi / 2 + 0.5, pi / 2, 0.1), pi / 2 + 0.4);
  EXPECT_DOUBLE_EQ(spring_laws::creased_rest_angle(pi / 2 - 0.5, pi / 2, 0.1), pi / 2 - 0.4);
  // Within the yield angle: unchanged, to the bit.
  EXPECT_EQ(spring_laws::creased_rest_angle(pi / 2 + 0.05, pi / 2, 0.1), pi / 2);
  // Folded flat or opened straight, the rest angle follows to the yield angle short of it.
  EXPECT_EQ(spring_laws::creased_rest_angle(0.0, 2.0, 0.5), 0.5);
  EXPECT_EQ(spring_laws::creased_rest_angle(pi, 0.5, 0.2), pi - 0.2);
  // An angle a rounding past an end (the clamp's case) leaves a rest angle in [0, pi].
  EXPECT_EQ(spring_laws::creased_rest_angle(std::nextafter(pi, 4.0), 0.5, 0.0), pi);
  EXPECT_EQ(spring_laws::creased_rest_angle(-1e-17, 0.5, 0.0), 0.0);
}

}  // namespace
}  // namespace clothsim
