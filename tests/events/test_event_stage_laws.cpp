// The event stage (events/spring_events.h) applies the laws of DESIGN.md section 3 to the model as
// it has become, not as it was built: a connector that has yielded still breaks at its strain
// against its original length; the return mapping acts in compression as in tension; a crease
// folded one way and then back moves its rest angle back by the closed form. Each case places the
// particles by hand and runs one apply(), so the expected values are the laws' closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "event_fixtures.h"
#include "events/spring_events.h"
#include "forces/element.h"
#include "forces/forces.h"
#include "model/model_edits.h"

namespace clothsim {
namespace {

using namespace clothsim::testing;

constexpr double kPi = std::numbers::pi;

ClothModel strip_with(int particles, const SpringLimits& limits) {
  ClothModel model = strip(particles);
  apply_spring_limits(model, limits);
  return model;
}

SpringEventCounts apply_at(ClothModel& model, ClothState& state) {
  SpringEvents events;
  return events.apply(model, state, 1);
}

TEST(EventStageLaws, AYieldedConnectorBreaksAtItsStrainAgainstItsOriginalLength) {
  SpringLimits limits;
  limits.break_strain = 0.3;
  limits.yield_strain = 0.05;
  for (const double length : {1.25, 1.35}) {
    ClothModel model = strip_with(2, limits);
    ASSERT_EQ(model.connector_break_strain[0], 0.3);
    // As if it had yielded to a rest length of 1.2 m: against it, both lengths are within the
    // yield (4.2 %) and far from the break strain (12.5 %); against the original 1 m, 1.35 m is
    // past the break strain and 1.25 m is not.
    set_connector_rest_length(model, 0, 1.2);
    ClothState state = make_rest_state(model);
    state.position[1] = state.position[0] + Vec3{length, 0.0, 0.0};
    const SpringEventCounts counts = apply_at(model, state);
    EXPECT_EQ(counts.breaks, length > 1.3 ? 1u : 0u) << "at " << length << " m";
    EXPECT_EQ(model.connector_live[0], length > 1.3 ? 0 : 1) << "at " << length << " m";
    EXPECT_EQ(counts.yields, 0u);
  }
}

TEST(EventStageLaws, AConnectorCompressedPastItsYieldShortensToTheReturnMapping) {
  SpringLimits limits;
  limits.yield_strain = 0.05;
  ClothModel model = strip_with(2, limits);
  ClothState state = make_rest_state(model);
  state.position[1] = state.position[0] + Vec3{0.8, 0.0, 0.0};  // strain -20 %
  const SpringEventCounts counts = apply_at(model, state);
  EXPECT_EQ(counts.yields, 1u);
  // L' = l / (1 - y): the elastic strain left is exactly -y.
  EXPECT_NEAR(model.connector_rest_length[0], 0.8 / 0.95, 1e-15);
  EXPECT_NEAR(0.8 / model.connector_rest_length[0] - 1.0, -0.05, 1e-14);
  // Within the yield of the new rest length, nothing more happens.
  state.position[1] = state.position[0] + Vec3{0.85, 0.0, 0.0};
  EXPECT_EQ(apply_at(model, state).yields, 0u);
  EXPECT_NEAR(model.connector_rest_length[0], 0.8 / 0.95, 1e-15);
}

// A 1 x 3 strip: the opposite spring at the middle particle, its arms along x. The far end lifted
// to angle `angle` at the middle.
void fold_to(ClothState& state, double angle) {
  const Vec3 middle = state.position[1];
  state.position[2] = middle + Vec3{-std::cos(angle), 0.0, std::sin(angle)};
}

std::size_t opposite_spring(const ClothModel& model) {
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    if (model.radial_kind[r] == RadialKind::opposite) return r;
  }
  ADD_FAILURE() << "no opposite spring";
  return 0;
}

TEST(EventStageLaws, ACreaseFoldedOneWayAndThenBackFollowsTheClosedForm) {
  SpringLimits limits;
  limits.opposite_yield_angle = 0.2;
  ClothModel model = strip_with(3, limits);
  const std::size_t r = opposite_spring(model);
  ClothState state = make_rest_state(model);
  ASSERT_NEAR(model.radial_rest_angle[r], kPi, 1e-15);
  // Folded to pi - 0.6: the rest angle follows to within the yield angle, pi - 0.4.
  fold_to(state, kPi - 0.6);
  EXPECT_EQ(apply_at(model, state).creases, 1u);
  EXPECT_NEAR(model.radial_rest_angle[r], kPi - 0.4, 1e-12);
  // Back to flat: 0.4 from the new rest, past the yield, so the rest angle comes back to pi - 0.2.
  fold_to(state, kPi);
  EXPECT_EQ(apply_at(model, state).creases, 1u);
  EXPECT_NEAR(model.radial_rest_angle[r], kPi - 0.2, 1e-12);
  // Folded the other way to pi - 0.5: an unsigned angle, so the same law from pi - 0.2: pi - 0.3.
  state.position[2] = state.position[1] + Vec3{-std::cos(kPi - 0.5), 0.0, -std::sin(kPi - 0.5)};
  EXPECT_EQ(apply_at(model, state).creases, 1u);
  EXPECT_NEAR(model.radial_rest_angle[r], kPi - 0.3, 1e-12);
}

// A crease whose spring has an arm inside the fade of vanishing arms (forces/element_math.inc):
// the work the event stage books is the change of the faded energy the balance sums, and a
// connector that breaks there releases its radial springs' faded energy.
TEST(EventStageLaws, WorkBookedInTheFadeIsTheFadedEnergysChange) {
  SpringLimits limits;
  limits.opposite_yield_angle = 0.2;
  ClothModel model = strip_with(3, limits);
  const std::size_t r = opposite_spring(model);
  ClothState state = make_rest_state(model);
  // Folded to pi - 0.6 with the arm to particle 2 at 30 % of its length: phi(0.6) = 0.68.
  const Vec3 middle = state.position[1];
  state.position[2] = middle + 0.3 * Vec3{-std::cos(kPi - 0.6), 0.0, std::sin(kPi - 0.6)};
  const double before = compute_energy(model, state).radial_opposite;
  EXPECT_EQ(apply_at(model, state).creases, 1u);
  EXPECT_NEAR(model.radial_rest_angle[r], kPi - 0.4, 1e-12);
  const double after = compute_energy(model, state).radial_opposite;
  // Unfaded, the change would be 1/2 k (0.2^2 - 0.6^2); faded, phi(0.6) times that.
  const double unfaded = 0.5 * model.radial_stiffness[r] * (0.2 * 0.2 - 0.6 * 0.6);
  EXPECT_NEAR(after - before, element::arm_fade(0.3, 0.5).value * unfaded, 1e-9 * std::abs(unfaded));
  EXPECT_NEAR(state.plastic_work, after - before, 1e-12 * std::abs(unfaded));
}

}  // namespace
}  // namespace clothsim
