// What limits the step at a particle, for the diagnosis of a step-size underflow: the spring that
// touches the particle with the largest error and is nearest a kink of the radial angle, else the
// one furthest from its rest.
//
// The radial angle theta = atan2(|u x w|, u . w) of a spring's two arms u and w is not
// differentiable where the arms become parallel (theta = 0) or opposite (theta = pi): its gradient
// turns by 180 degrees there. A spring whose rest angle is away from that end (an adjacent spring,
// rest 90 degrees, at 0 or 180; an opposite one, rest 180, folded shut at 0) pushes with a force
// of k |theta0 - theta_kink| that flips direction as the angle passes the kink, which no step
// size resolves (docs/cli.md, "A failed simulation"). An opposite spring at 180 degrees
// is not at a kink: its energy (theta - pi)^2 is smooth there. The bound on the stable step of a
// whole model, per particle, is integrators/stable_step.h's.
#pragma once

#include <cstddef>
#include <span>
#include <string>

#include "core/vec3.h"
#include "model/cloth_model.h"

namespace clothsim {

// How near a kink a radial spring counts as at it, rad (2 degrees).
inline constexpr double kKinkWindow = 0.035;
// A connector shorter than this fraction of its rest length counts as collapsing: one particle is
// passing through the other. The radial springs on it fade out as it vanishes (their forces
// would otherwise grow as 1 / length: forces/element_math.inc, kRadialFadeFraction), but the
// connector's own force k (l - L) u turns round as l passes through 0. The paper's hanging sheets
// died of this before the fade (docs/performance.md, "Soak").
inline constexpr double kCollapsedLength = 0.1;

struct StepLimit {
  enum class Kind { none, connector, radial };
  Kind kind = Kind::none;
  std::size_t element = 0;  // connector or radial spring index
  bool at_kink = false;     // a radial spring within kKinkWindow of a kink
  double kink_angle = 0.0;  // rad, 0 or pi, when at_kink
  double angle = 0.0;       // rad, a radial spring's angle now
  double strain = 0.0;      // a connector's l / L - 1
  double rate = 0.0;        // 1/s, the larger of its damping rate and its elastic frequency
  bool collapsed = false;   // a connector anywhere in the sheet below kCollapsedLength
};

// The shortest live connector anywhere in the sheet if it is collapsing (kCollapsedLength), which
// limits every step whichever particle's error is largest; else the live spring touching
// `particle` (a connector at either end, a radial spring as centre or arm) at a kink, the nearest
// first; else, where a spring is far from rest (kFarFromRest: a strain
// or an angle from rest in rad), the one furthest; else the stiffest, whose rate (its damping
// rate c / m, or c / (m L^2) for a radial spring, or its elastic frequency, the larger) bounds an
// explicit method's stable step.
inline constexpr double kFarFromRest = 0.05;
StepLimit find_step_limit(const ClothModel& model, std::span<const Vec3> position, std::size_t particle);

// "the adjacent radial spring centred at particle 5 (row 1, col 1), arms to particle 6 (row 1,
// col 2) and particle 9 (row 2, col 1), is at 179.6 degrees, 0.4 degrees from its kink at 180
// degrees, where the angle is not differentiable and the spring's force turns abruptly"; "" when
// no live spring touches the particle.
std::string describe_step_limit(const ClothModel& model, const StepLimit& limit, std::span<const Vec3> position);

}  // namespace clothsim
