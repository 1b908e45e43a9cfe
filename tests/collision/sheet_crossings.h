// A brute-force check that a sheet does not pass through itself, for tests of self-collision.
//
// It is written independently of the solver (nothing from src/collision/), so that a bug in the
// self-collision stage cannot hide in a shared helper: the sheet's triangles and edges are built
// here from the lattice rule, and every (edge, triangle) pair is tested with a plain
// segment-triangle test, O(edges x triangles) (about 10^7 pairs for a 50 x 50 sheet, a fraction
// of a second with the bounding-box reject below).
//
// The sheet's surface is the lattice triangulation of model/sheet_mesh.h: quad (i, j) is cut into
// triangles (i,j)(i+1,j)(i,j+1) and (i,j+1)(i+1,j)(i+1,j+1), particle (i, j) being i*cols + j.
// Its edges are the triangles' edges: the lattice connectors and the quads' diagonals.
// A torn sheet (model.connector_live[e] == 0) keeps a triangle only while both of its connector
// edges are intact, and an edge only while it is an edge of a kept triangle or a live connector
// (a live connector whose triangles are both gone is a thread of cloth, and still may not pass
// through the sheet).
//
// A crossing is an edge passing through the interior of a triangle that contains neither of the
// edge's endpoints (an edge and a triangle sharing a particle meet at that particle, which is no
// crossing). The test uses the signs of four-point volumes (orient3d): the edge's endpoints must
// lie strictly on opposite sides of the triangle's plane, and the edge's line must pass strictly
// inside each of the triangle's three edges. Degenerate contact (an endpoint exactly on the
// triangle, an edge through a triangle's edge or vertex, an edge lying in the triangle's plane)
// is NOT a crossing: touching is what self-collision at a thickness allows, and where the sheet
// truly passes through itself some neighbouring pair crosses strictly. The volumes are plain
// double arithmetic, not exact predicates, so a configuration within rounding of touching may
// count either way; the sheets tests look at pass through each other by far more than rounding.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/vec3.h"
#include "model/cloth_model.h"

namespace clothsim::testing {

// The parts of the sheet the check counts, by particle index.
struct SheetSurface {
  std::vector<std::array<std::uint32_t, 2>> edges;      // [edges] (a, b), a < b, each once
  std::vector<std::array<std::uint32_t, 3>> triangles;  // [triangles] as in the lattice rule above
};

// One crossing: `edge` passes through `triangle`.
struct SheetCrossing {
  std::array<std::uint32_t, 2> edge;
  std::array<std::uint32_t, 3> triangle;
};

// The triangles and edges of model's lattice (model.rows x model.cols), torn ones left out.
SheetSurface sheet_surface(const ClothModel& model);

// Whether segment p-q passes strictly through the interior of triangle a-b-c (see the top of
// this file: touching and coplanar configurations are not crossings).
bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c);

// Every (edge, triangle) pair of the sheet at `position` [particle_count()] that crosses, the
// triangle not containing an endpoint of the edge; in edge order, then triangle order.
std::vector<SheetCrossing> sheet_crossings(const ClothModel& model, std::span<const Vec3> position);

// How many there are: sheet_crossings(model, position).size().
std::size_t count_sheet_crossings(const ClothModel& model, std::span<const Vec3> position);

}  // namespace clothsim::testing
