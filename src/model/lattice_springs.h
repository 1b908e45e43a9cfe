// The order of a lattice's springs, the one build_lattice() numbers them in: the table of
// model/lattice_springs.inc (shared with the compute shaders) and a walker over the springs in
// that order. The lattice kernel (forces/lattice_kernel.h) and the Vulkan backend's lattice path
// lay out the springs' parameters by particle and find each spring's place by walking the
// lattice again, which needs no table of where each spring goes (8 bytes per connector and radial
// spring, 32 bytes per particle).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/shared_text.h"

namespace clothsim {

#include "model/lattice_springs.inc"

// Whether radial spring `pair` of a particle joins opposite arms (rest angle pi), not adjacent ones.
constexpr bool radial_pair_is_opposite(std::size_t pair) { return (kRadialArmB[pair] + 2) % 4 == kRadialArmC[pair]; }

// The neighbour of particle p along `arm` in a lattice of `cols` columns (the arm must exist).
constexpr std::uint32_t lattice_neighbour(std::uint32_t p, int arm, std::size_t cols) {
  const auto c = static_cast<std::uint32_t>(cols);
  return arm == 0 ? p + 1 : arm == 1 ? p + c : arm == 2 ? p - 1 : p - c;
}

// Visits the springs of a rows x cols lattice in build_lattice()'s order, which is the order of
// the model's element arrays: connector(e, p, south) for connector e from particle p east (south
// false) or south, and radial(r, p, pair) for radial spring r centred at p between the arms
// kRadialArmB[pair] and kRadialArmC[pair]. Stops at the first visit that returns false; returns
// whether every visit returned true.
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
      const std::array<bool, 4> arm{j + 1 < cols, i + 1 < rows, j > 0, i > 0};
      for (std::size_t pair = 0; pair < static_cast<std::size_t>(kRadialsPerParticle); ++pair) {
        if (!arm[static_cast<std::size_t>(kRadialArmB[pair])] || !arm[static_cast<std::size_t>(kRadialArmC[pair])]) {
          continue;
        }
        if (!radial(r++, p, pair)) return false;
      }
    }
  }
  return true;
}

}  // namespace clothsim
