#include "model/anchor.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace clothsim {
namespace {

// Index of the key that starts the segment containing t: keys[k].time <= t < keys[k + 1].time.
// Only for keys.front().time <= t < keys.back().time.
std::size_t segment_of(const std::vector<AnchorKey>& keys, double t) {
  const auto after =
      std::upper_bound(keys.begin(), keys.end(), t, [](double time, const AnchorKey& key) { return time < key.time; });
  return static_cast<std::size_t>(after - keys.begin()) - 1;
}

}  // namespace

Vec3 AnchorPath::position(double t) const {
  switch (kind) {
    case AnchorPathKind::fixed: return origin;
    case AnchorPathKind::linear: return origin + t * velocity;
    case AnchorPathKind::sinusoid: {
      const double omega = 2.0 * std::numbers::pi * frequency;
      return origin + (std::sin(omega * t + phase) - std::sin(phase)) * amplitude;
    }
    case AnchorPathKind::keyframes: {
      if (keys.empty()) return origin;
      if (t <= keys.front().time) return origin + keys.front().offset;
      if (t >= keys.back().time) return origin + keys.back().offset;
      const std::size_t k = segment_of(keys, t);
      const AnchorKey& from = keys[k];
      const AnchorKey& to = keys[k + 1];
      // s = 0 exactly at a key, so a key's position is reproduced bit for bit.
      const double s = (t - from.time) / (to.time - from.time);
      return origin + from.offset + s * (to.offset - from.offset);
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
    case AnchorPathKind::fixed: return {};
    case AnchorPathKind::linear: return velocity;
    case AnchorPathKind::sinusoid: {
      const double omega = 2.0 * std::numbers::pi * frequency;
      return (omega * std::cos(omega * t + phase)) * amplitude;
    }
    case AnchorPathKind::keyframes: {
      if (keys.size() < 2 || t < keys.front().time || t >= keys.back().time) return {};
      const std::size_t k = segment_of(keys, t);
      return (keys[k + 1].offset - keys[k].offset) / (keys[k + 1].time - keys[k].time);
    }
    case AnchorPathKind::driven: return t <= end_time ? velocity : Vec3{};
  }
  return {};
}

Vec3 AnchorPath::velocity_before(double t) const {
  if (kind != AnchorPathKind::keyframes) return velocity_at(t);
  if (keys.size() < 2 || t <= keys.front().time || t > keys.back().time) return {};
  // The segment (keys[k].time, keys[k + 1].time] that holds t.
  const auto end =
      std::lower_bound(keys.begin(), keys.end(), t, [](const AnchorKey& key, double time) { return key.time < time; });
  const std::size_t k = static_cast<std::size_t>(end - keys.begin()) - 1;
  return (keys[k + 1].offset - keys[k].offset) / (keys[k + 1].time - keys[k].time);
}

Vec3 AnchorPath::acceleration(double t) const {
  if (kind != AnchorPathKind::sinusoid) return {};
  const double omega = 2.0 * std::numbers::pi * frequency;
  return (-omega * omega * std::sin(omega * t + phase)) * amplitude;
}

double AnchorPath::next_key_after(double t) const {
  if (kind != AnchorPathKind::keyframes) return std::numeric_limits<double>::infinity();
  const auto after =
      std::upper_bound(keys.begin(), keys.end(), t, [](double time, const AnchorKey& key) { return time < key.time; });
  return after == keys.end() ? std::numeric_limits<double>::infinity() : after->time;
}

}  // namespace clothsim
