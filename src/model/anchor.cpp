#include "model/anchor.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace clothsim {

Vec3 AnchorPath::position(double t) const {
  switch (kind) {
    case AnchorPathKind::fixed:
      return origin;
    case AnchorPathKind::linear:
      return origin + t * velocity;
    case AnchorPathKind::sinusoid: {
      const double omega = 2.0 * std::numbers::pi * frequency;
      return origin + (std::sin(omega * t + phase) - std::sin(phase)) * amplitude;
    }
    case AnchorPathKind::driven:
      // A held particle (velocity zero, end_time infinite) gives exactly origin.
      if (velocity == Vec3{}) return origin;
      return origin + (std::min(t, end_time) - start_time) * velocity;
  }
  return origin;
}

Vec3 AnchorPath::velocity_at(double t) const {
  switch (kind) {
    case AnchorPathKind::fixed:
      return {};
    case AnchorPathKind::linear:
      return velocity;
    case AnchorPathKind::sinusoid: {
      const double omega = 2.0 * std::numbers::pi * frequency;
      return (omega * std::cos(omega * t + phase)) * amplitude;
    }
    case AnchorPathKind::driven:
      return t <= end_time ? velocity : Vec3{};
  }
  return {};
}

Vec3 AnchorPath::acceleration(double t) const {
  if (kind != AnchorPathKind::sinusoid) return {};
  const double omega = 2.0 * std::numbers::pi * frequency;
  return (-omega * omega * std::sin(omega * t + phase)) * amplitude;
}

}  // namespace clothsim
