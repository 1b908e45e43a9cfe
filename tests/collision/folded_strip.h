// A 3 x 6 strip folded in half over itself, with one particle of its top layer moved 10 cm down
// through the bottom layer within a step, at neither end within the thickness of anything: the
// case of self-collision's continuous stage alone (tests/collision/test_self_contacts.cpp, and the
// device's in tests/gpu).
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "model/cloth_model.h"

namespace clothsim::testing {

struct FoldedStrip {
  ClothModel model;
  std::vector<Vec3> start;  // the step's start: the fold, uncrossed
  ClothState state;         // the step's end as taken: `moved` through the bottom layer at -10 m/s
  std::size_t moved = 0;    // row 1, column 5: above the bottom layer's cell (0..0.1, 0.1..0.2)
};

inline FoldedStrip folded_strip() {
  LatticeDef def;
  def.rows = 3;
  def.cols = 6;
  def.spacing = 0.1;
  FoldedStrip strip{build_lattice(def, Environment{{0.0, 0.0, 0.0}, 0.0}, {}), {}, {}, 1 * 6 + 5};
  strip.model.collision.self = true;
  strip.model.collision.thickness = 0.005;
  ClothState& state = strip.state;
  state = make_rest_state(strip.model);
  // Columns 0-2 flat at y = 0; column 3 the crease; columns 4-5 folded back 5 cm above, shifted so
  // that no top particle lies over a bottom one.
  const std::array<double, 6> column_x{0.0, 0.1, 0.2, 0.25, 0.23, 0.13};
  const std::array<double, 6> column_y{0.0, 0.0, 0.0, 0.025, 0.05, 0.05};
  for (int row = 0; row < def.rows; ++row) {
    for (int col = 0; col < def.cols; ++col) {
      const double shift = col >= 4 ? 0.04 : 0.0;
      state.position[static_cast<std::size_t>(row * def.cols + col)] =
          Vec3{column_x[static_cast<std::size_t>(col)], column_y[static_cast<std::size_t>(col)], 0.1 * row + shift};
    }
  }
  strip.start = state.position;
  state.position[strip.moved].y = -0.05;
  state.velocity[strip.moved] = Vec3{0.0, -10.0, 0.0};
  state.time = 0.01;
  return strip;
}

}  // namespace clothsim::testing
