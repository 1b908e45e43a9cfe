// The lattice kernel's own layout, shared by its two source files (lattice_kernel.cpp, the vector
// loops, and lattice_kernel_parameters.cpp, which prepares the scratch and copies the
// parameters): the scratch arrays. The order of a particle's springs, and the walk over the
// lattice's springs in the model's order, are the model's (model/lattice_springs.h). The design
// is in lattice_kernel.h.
#pragma once

#include <cstddef>

#include "model/lattice_springs.h"

namespace clothsim::lattice_layout {

// The scratch arrays, each `stride_` Reals (double or float: the precision of the forces), indexed
// by particle (with padding both sides).
// clang-format off
enum Array : std::size_t {
  // East connector of each particle (to col + 1) and south connector (to row + 1): unit vector,
  // 1/length (0 where the connector does not exist or has zero length), tension (N), and the
  // neighbour's velocity relative to the particle's (m/s; 0 where there is no connector). The
  // relative velocities are differences of the float64 state, taken once per connector: the
  // radial springs of both ends read them, and in float32 (lattice_kernel.h, "Precision") they
  // keep the digits a difference of two rounded absolute velocities would lose. Then the fade of
  // the radial springs using the connector as an arm (element_math.inc, kRadialFadeFraction):
  // phi(l / f) and d phi / d l (1/m), 1 and 0 where it does not exist.
  kEastX, kEastY, kEastZ, kEastInverseLength, kEastTension, kEastVelocityX, kEastVelocityY, kEastVelocityZ,
  kEastFade, kEastFadeSlope,
  kSouthX, kSouthY, kSouthZ, kSouthInverseLength, kSouthTension, kSouthVelocityX, kSouthVelocityY, kSouthVelocityZ,
  kSouthFade, kSouthFadeSlope,
  kConnectorPower,  // damping power of the east and south connectors, W
  // Force that the radial springs centred at a particle exert on each of its four neighbours, N.
  kToEastX, kToEastY, kToEastZ,
  kToSouthX, kToSouthY, kToSouthZ,
  kToWestX, kToWestY, kToWestZ,
  kToNorthX, kToNorthY, kToNorthZ,
  kPower,  // damping power of everything owned by the particle (2 connectors, 6 radials), W
  kSingular,  // > 0 where one of the particle's radial springs is singular
  // Per-spring parameters, copied from the model by refresh() whenever its revision moves.
  // East and south connector: stiffness, damping, rest length, 1 if intact (0 if broken or
  // missing), and the fade length of the radial springs using it (m). Radial spring i of the particle (i in the order of model/lattice_springs.inc: (E,S),
  // (S,W), (W,N), (N,E), (E,W), (S,N)): stiffness, damping, rest angle; 0, 0 where it is broken or
  // missing.
  kEastStiffness, kEastDamping, kEastRestLength, kEastLive, kEastFadeLength,
  kSouthStiffness, kSouthDamping, kSouthRestLength, kSouthLive, kSouthFadeLength,
  kRadialStiffness, kRadialDamping = kRadialStiffness + 6, kRadialRestAngle = kRadialDamping + 6,
  kArrayCount = kRadialRestAngle + 6
};
// clang-format on
// A uniform sheet (LatticeKernel::uniform()) keeps only the arrays before the parameters.
inline constexpr std::size_t kUniformArrayCount = kEastStiffness;

}  // namespace clothsim::lattice_layout
