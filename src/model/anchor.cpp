#include "model/anchor.h"

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
  }
  return {};
}

Vec3 AnchorPath::acceleration(double t) const {
  if (kind != AnchorPathKind::sinusoid) return {};
  const double omega = 2.0 * std::numbers::pi * frequency;
  return (-omega * omega * std::sin(omega * t + phase)) * amplitude;
}

}  // namespace clothsim
