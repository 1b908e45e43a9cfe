// The shared arctangent (forces/arctangent.inc) over the upper half plane, the range the
// shaders' element formulas ask of it: within 2 ulps of libm in double and 4 float ulps in float,
// exact where the answer is, and the reflection x -> -x exact up to the last bit of pi. The first
// quadrant, which the lattice kernel calls, is held to libm in test_lattice_kernel.cpp (double)
// and test_float32_forces.cpp (float); tests/gpu/test_shared_laws.cpp holds the shaders' to these.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "forces/vector_math.h"
#include "test_support.h"

namespace clothsim {
namespace {

using testing::TestRandom;

// Distance in units in the last place of `exact` between two finite values of the same sign.
template <typename Real>
double ulps(Real value, Real exact) {
  if (value == exact) return 0.0;
  const Real step = std::nextafter(std::abs(exact), std::numeric_limits<Real>::infinity()) - std::abs(exact);
  return static_cast<double>(std::abs(value - exact) / step);
}

TEST(Arctangent, UpperHalfIsWithinTwoUlpsOfLibm) {
  TestRandom random(47);
  double worst = 0.0;
  double worst_float = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const double y = std::pow(10.0, random.uniform(-14, 3));
    const double x = (random.uniform(0, 1) < 0.5 ? -1.0 : 1.0) * std::pow(10.0, random.uniform(-14, 3));
    worst = std::max(worst, ulps(vector_math::atan2_upper_half(y, x), std::atan2(y, x)));
    const auto yf = static_cast<float>(y);
    const auto xf = static_cast<float>(x);
    worst_float = std::max(worst_float, ulps(vector_math::atan2_upper_half(yf, xf), std::atan2(yf, xf)));
  }
  EXPECT_LE(worst, 2.0);
  EXPECT_LE(worst_float, 4.0);
}

TEST(Arctangent, UpperHalfIsExactWhereTheAngleIs) {
  constexpr double pi = std::numbers::pi;
  EXPECT_EQ(vector_math::atan2_upper_half(0.0, 0.0), 0.0);  // as C's atan2(+0, +0)
  EXPECT_EQ(vector_math::atan2_upper_half(0.0, 1.0), 0.0);
  EXPECT_EQ(vector_math::atan2_upper_half(0.0, -1.0), pi);
  EXPECT_EQ(vector_math::atan2_upper_half(1.0, 0.0), pi / 2);
  EXPECT_EQ(vector_math::atan2_upper_half(1.0, 1.0), pi / 4);
  EXPECT_EQ(vector_math::atan2_upper_half(1.0, -1.0), 3 * pi / 4);
  EXPECT_EQ(vector_math::atan2_upper_half(0.0f, -1.0f), std::numbers::pi_v<float>);
  EXPECT_EQ(vector_math::atan2_upper_half(1.0f, 0.0f), std::numbers::pi_v<float> / 2);
}

// pi - theta near a straight pair keeps its digits: the reflected angle of a tiny y is pi - y/|x|
// to within pi's last bit.
TEST(Arctangent, ReflectionKeepsTheDigitsNearPi) {
  for (const double y : {1e-8, 1e-12, 1e-16, 1e-300}) {
    const double angle = vector_math::atan2_upper_half(y, -1.0);
    EXPECT_LE(ulps(angle, std::atan2(y, -1.0)), 1.0) << y;
    EXPECT_EQ(vector_math::atan2_upper_half(y, 1.0), y) << y;
  }
}

}  // namespace
}  // namespace clothsim
