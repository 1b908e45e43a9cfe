// Initial conditions a scene can set on top of the flat lattice at rest.
#pragma once

#include <cstdint>

#include "core/vec3.h"
#include "model/cloth_model.h"

namespace clothsim {

struct InitialConditions {
  Vec3 velocity;                // uniform velocity of every free particle, m/s
  Vec3 angular_velocity;        // rigid spin about the lattice centre, rad/s (axis * rate)
  double position_noise = 0.0;  // each free coordinate moved by a uniform value in [-a, a], m
  double velocity_noise = 0.0;  // each free velocity component changed likewise, m/s
  std::uint64_t seed = 1;       // seed of the perturbation; the same seed gives the same sheet
};

// Applies `initial` to a state made by make_rest_state(). Anchored particles keep their path's
// position and velocity. The random numbers come from a fixed SplitMix64 stream, so a seed gives
// the same perturbation on every platform and standard library.
void apply_initial_conditions(const ClothModel& model, const InitialConditions& initial, ClothState& state);

}  // namespace clothsim
