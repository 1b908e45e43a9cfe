// The sheet as self-collision sees it: the lattice's triangles and edges (collision/self_contacts.h).
//
// The physics has no triangles; these are the ones of the output mesh (model/sheet_mesh.h): quad
// (i, j) is cut into (i,j)(i+1,j)(i,j+1) and (i,j+1)(i+1,j)(i+1,j+1). The edges are the
// triangles' edges: the connectors and the quads' diagonals. Self-collision keeps every particle
// away from every triangle and every edge away from every edge that does not share a particle
// with it, so two pieces of sheet can neither pass through each other nor come closer than the
// thickness.
//
// Torn sheets: a triangle is cloth while both of its connectors are intact; a broken connector
// takes the triangle on each side of it away (the quarter cells the renderer draws there are not
// collided). An edge is collided while it is an intact connector or the diagonal of a remaining
// triangle. A torn edge's particles still collide, as points, with every remaining triangle.
// The lists are rebuilt when the set of broken connectors changes, never otherwise.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "model/cloth_model.h"

namespace clothsim {

struct SheetElements {
  std::vector<std::array<std::uint32_t, 3>> triangle;  // particle indices, lattice order
  std::vector<std::array<std::uint32_t, 2>> edge;      // particle indices: connectors, then diagonals

  // What the lists were built for.
  std::size_t built_particles = 0;
  std::size_t built_broken = static_cast<std::size_t>(-1);
};

// How many triangles and edges an untorn lattice of `counts` has: two triangles a cell; the
// connectors and one diagonal a cell. The most a torn one has, for what is sized before the
// elements are built (SelfContacts::bytes_for, gpu::DeviceSelfContacts::bytes_for).
struct SheetElementCounts {
  std::size_t triangles = 0;
  std::size_t edges = 0;
};
SheetElementCounts sheet_element_counts(const LatticeCounts& counts);

// Brings `elements` up to date with `model` (a rows x cols lattice): rebuilt when the particle
// count or the number of broken connectors differs from what they were built for.
void refresh_sheet_elements(const ClothModel& model, SheetElements& elements);

}  // namespace clothsim
