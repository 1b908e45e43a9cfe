// The lattice kernel's own layout, shared by its two source files: the scratch arrays and the
// order of a particle's radial springs (lattice_kernel.cpp, the vector loops), and the walk over
// the lattice's springs in the model's order (lattice_kernel_parameters.cpp, which prepares the
// scratch and copies the parameters), and the Vulkan backend's lattice path, which lays out the
// springs' parameters by particle the same way (gpu/device_integrator.cpp). The design is in
// lattice_kernel.h.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

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
  // keep the digits a difference of two rounded absolute velocities would lose.
  kEastX, kEastY, kEastZ, kEastInverseLength, kEastTension, kEastVelocityX, kEastVelocityY, kEastVelocityZ,
  kSouthX, kSouthY, kSouthZ, kSouthInverseLength, kSouthTension, kSouthVelocityX, kSouthVelocityY, kSouthVelocityZ,
  kConnectorPower,  // damping power of the east and south connectors, W
  // Force that the radial springs centred at a particle exert on each of its four neighbours, N.
  kToEastX, kToEastY, kToEastZ,
  kToSouthX, kToSouthY, kToSouthZ,
  kToWestX, kToWestY, kToWestZ,
  kToNorthX, kToNorthY, kToNorthZ,
  kPower,  // damping power of everything owned by the particle (2 connectors, 6 radials), W
  kSingular,  // > 0 where one of the particle's radial springs is singular
  // Per-spring parameters, copied from the model by refresh() whenever its revision moves.
  // East and south connector: stiffness, damping, rest length, and 1 if intact (0 if broken or
  // missing). Radial spring i of the particle (i in the order of kPairs: (E,S), (S,W), (W,N),
  // (N,E), (E,W), (S,N)): stiffness, damping, rest angle; 0, 0 where it is broken or missing.
  kEastStiffness, kEastDamping, kEastRestLength, kEastLive,
  kSouthStiffness, kSouthDamping, kSouthRestLength, kSouthLive,
  kRadialStiffness, kRadialDamping = kRadialStiffness + 6, kRadialRestAngle = kRadialDamping + 6,
  kArrayCount = kRadialRestAngle + 6
};
// clang-format on
// A uniform sheet (LatticeKernel::uniform()) keeps only the arrays before the parameters.
inline constexpr std::size_t kUniformArrayCount = kEastStiffness;

// The radial springs of a particle as pairs of its connectors: directions 0 east, 1 south,
// 2 west, 3 north; the four adjacent pairs, then the two opposite ones (build_lattice's order).
inline constexpr std::array<std::array<int, 2>, 6> kPairs = {{{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 2}, {1, 3}}};

// Visits the springs of a rows x cols lattice in build_lattice()'s order, which is the order of
// the model's element arrays: connector(e, p, south) for connector e from particle p east (south
// false) or south, and radial(r, p, pair) for radial spring r centred at p between the arms of
// kPairs[pair]. Stops at the first visit that returns false; returns whether every visit
// returned true. Walking the lattice like this needs no table of where each spring goes (8 bytes
// per connector and radial spring, 32 bytes per particle).
template <typename Connector, typename Radial>
bool for_each_lattice_spring(std::size_t rows, std::size_t cols, Connector&& connector, Radial&& radial) {
  std::uint32_t e = 0;
  for (std::size_t i = 0; i < rows; ++i) {
    for (std::size_t j = 0; j < cols; ++j) {
      const auto p = static_cast<std::uint32_t>(i * cols + j);
      if (j + 1 < cols && !connector(e++, p, false)) return false;
      if (i + 1 < rows && !connector(e++, p, true)) return false;
    }
  }
  std::uint32_t r = 0;
  for (std::size_t i = 0; i < rows; ++i) {
    for (std::size_t j = 0; j < cols; ++j) {
      const auto p = static_cast<std::uint32_t>(i * cols + j);
      // Arms 0 east, 1 south, 2 west, 3 north.
      const std::array<bool, 4> arm{j + 1 < cols, i + 1 < rows, j > 0, i > 0};
      for (std::size_t pair = 0; pair < kPairs.size(); ++pair) {
        const auto [b, c] = kPairs[pair];
        if (!arm[static_cast<std::size_t>(b)] || !arm[static_cast<std::size_t>(c)]) continue;
        if (!radial(r++, p, pair)) return false;
      }
    }
  }
  return true;
}

}  // namespace clothsim::lattice_layout
