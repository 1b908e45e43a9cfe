// Cuts across a lattice: which connectors a straight segment crosses.
//
// A cut is a segment in a 2D picture of the sheet, and it breaks every intact connector whose own
// segment between its particles' points it crosses (touching counts). The picture can be the
// screen (the viewer's knife, viewer/interaction.h) or the rest lattice itself, in (row, col)
// coordinates measured in particle spacings, so that a cut names the same springs whatever the
// sheet is doing: scenes pre-cut notches that way (scene key `cuts`), and viewer scripts cut that
// way. (2.5, -1) to (2.5, 9) crosses every connector between rows 2 and 3 of a 10-column sheet.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "model/cloth_model.h"

namespace clothsim {

// Intact connectors of `model` whose segment between the 2D points of its particles,
// `point` [particle_count()], crosses the segment from `from` to `to` (a connector whose
// particle has no point, NaN, is skipped). In connector index order.
std::vector<std::uint32_t> connectors_crossed(const ClothModel& model, std::span<const std::array<double, 2>> point,
                                              const std::array<double, 2>& from, const std::array<double, 2>& to);

// Intact connectors crossed by the segment between two rest-lattice points (row, col), in
// particle spacings.
std::vector<std::uint32_t> connectors_crossed_in_lattice(const ClothModel& model, const std::array<double, 2>& from,
                                                         const std::array<double, 2>& to);

}  // namespace clothsim
