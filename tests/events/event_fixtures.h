// Small sheets and runs shared by the event tests: strips pulled by anchors, one thread.
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include "model/cloth_model.h"
#include "model/spring_limits.h"
#include "sim/simulation.h"

namespace clothsim::testing {

// A 1 x `particles` strip of spacing 1 m along x with the paper's springs, no gravity.
inline ClothModel strip(int particles, std::vector<Anchor> anchors = {}, double connector_damping = 5.0) {
  LatticeDef def;
  def.rows = 1;
  def.cols = particles;
  def.connector.damping = connector_damping;
  return build_lattice(def, Environment{{0.0, 0.0, 0.0}, 0.0}, anchors);
}

// A particle held at `origin` and, from t = 0, moved at `velocity`; let go at `release` (s).
inline Anchor pulled(std::uint32_t particle, const Vec3& origin, const Vec3& velocity,
                     double release = std::numeric_limits<double>::infinity()) {
  Anchor anchor;
  anchor.particle = particle;
  anchor.path.kind = AnchorPathKind::linear;
  anchor.path.origin = origin;
  anchor.path.velocity = velocity;
  anchor.release_time = release;
  return anchor;
}

// A particle moved from `origin` at `velocity` until `stop` (s), then held there until `release`.
inline Anchor pulled_until(std::uint32_t particle, const Vec3& origin, const Vec3& velocity, double stop,
                           double release) {
  Anchor anchor;
  anchor.particle = particle;
  anchor.path.kind = AnchorPathKind::driven;
  anchor.path.origin = origin;
  anchor.path.velocity = velocity;
  anchor.path.start_time = 0.0;
  anchor.path.end_time = stop;
  anchor.release_time = release;
  return anchor;
}

inline Anchor held(std::uint32_t particle, const Vec3& origin) {
  Anchor anchor;
  anchor.particle = particle;
  anchor.path = AnchorPath::fixed_at(origin);
  return anchor;
}

inline SimulationSettings event_settings(int threads = 1) {
  SimulationSettings settings;
  settings.integrator.relative_tolerance = 1e-8;
  settings.integrator.absolute_tolerance = 1e-8;
  settings.threads = threads;
  return settings;
}

inline double distance(const ClothState& state, std::uint32_t a, std::uint32_t b) {
  return norm(state.position[b] - state.position[a]);
}

}  // namespace clothsim::testing
