// The triangle mesh of the sheet, shared by the exporters (io/obj) and the renderer (render/).
//
// The sheet is a rows x cols lattice of particles (model/cloth_model.h); particle (i, j) has index
// i*cols + j and, at rest, position ((j - (cols-1)/2) L, 0, (i - (rows-1)/2) L) with y up. Each
// lattice quad (i,j), (i,j+1), (i+1,j), (i+1,j+1) becomes two triangles, both wound
// counter-clockwise seen from +y on the rest lattice, so their face normals point +y:
//
//      (i,j) ----- (i,j+1)        -> +x (col)
//        |       /   |            |
//        |     /     |            v +z (row)
//        |   /       |
//     (i+1,j) --- (i+1,j+1)       triangles (i,j)(i+1,j)(i,j+1) and (i,j+1)(i+1,j)(i+1,j+1)
//
// Two ways to place the mesh's vertices (SheetMeshMode):
//   particles     one vertex per particle, at the particle: the default. Anchors and edges are
//                 where the physics has them.
//   cell_centres  the paper's rendering: one vertex per lattice cell, at the mean of its 4
//                 corner particles ((rows-1) x (cols-1) vertices; the paper, section 3). Cell
//                 (i, j) plays the role of particle (i, j) of a (rows-1) x (cols-1) lattice, so
//                 both modes share the triangulation code.
//
// Torn sheets: the mesh splits along broken connectors, so that no face spans a broken spring
// and, where springs remain, no cloth disappears. The particles are never split
// (model/model_edits.h); the mesh duplicates vertices instead. In particle mode a quad with a
// broken edge is drawn as 4 quarter cells, one per corner particle, from the connectors'
// midpoints (one per intact connector, one per end of a broken one) and one centre vertex per
// connected component of the quad's corners; an intact sheet keeps the mesh above exactly.
// Vertex p is particle p in particle mode, the split vertices follow (SheetMesh::vertex_source).
// docs/rendering.md ("Torn sheets") has the construction, its cell-centre form and what was
// rejected.
//
// The topology is rebuilt only when the set of broken connectors, the mode or the lattice changes
// (build_sheet_mesh compares the live mask it was built for); the positions and normals of every
// frame reuse the arrays, so a viewer or a video allocates nothing per frame until the next
// break. Vertex normals are area-weighted means of the face normals (unnormalised cross
// products: no angles needed).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/vec3.h"
#include "model/cloth_model.h"

namespace clothsim {

enum class SheetMeshMode : std::uint8_t {
  particles,     // vertices at the particles [rows * cols]
  cell_centres,  // vertices at the centres of the 4 particles of each cell [(rows-1) * (cols-1)]
};

// Triangles of a grid_rows x grid_cols grid of vertices indexed i*grid_cols + j, wound as above:
// [2 (grid_rows-1) (grid_cols-1)], empty when either side is below 2. Quad (i, j) owns
// triangles 2 (i (grid_cols-1) + j) and 2 (i (grid_cols-1) + j) + 1.
std::vector<std::array<std::uint32_t, 3>> grid_triangles(int grid_rows, int grid_cols);

// Triangles of the lattice, particle indices: grid_triangles(model.rows, model.cols).
std::vector<std::array<std::uint32_t, 3>> lattice_triangles(const ClothModel& model);

// Unit vertex normals [position.size()] of the mesh `triangles` at `position`, m: the
// area-weighted mean of the incident face normals. A vertex with no incident area (no faces, or
// all degenerate, or a non-finite sum) gets (0, 1, 0), the rest lattice's normal, so renderers
// never see a NaN.
std::vector<Vec3> vertex_normals(std::span<const Vec3> position,
                                 std::span<const std::array<std::uint32_t, 3>> triangles);
// The same, for particle positions of `model` [particle_count()].
std::vector<Vec3> vertex_normals(const ClothModel& model, std::span<const Vec3> position,
                                 std::span<const std::array<std::uint32_t, 3>> triangles);

// Grid size of the mesh in `mode`: {rows, cols} or {rows-1, cols-1} (0 where a side is 1).
std::array<int, 2> sheet_mesh_grid(const ClothModel& model, SheetMeshMode mode);

// What a vertex of a sheet mesh stands for (SheetMesh::vertex_source).
enum class SheetVertexKind : std::uint8_t {
  particle,            // particle `index`, at the particle
  connector_midpoint,  // intact connector `index`, at the midpoint of its ends
  connector_end,       // broken connector `index`, the half at its end `side` (0: a, 1: b)
  cell_centre,         // lattice quad (cell) `index` = i (cols-1) + j: the copy of its centre for
                       // the corners in `corners`, bit k for corner k of (i,j), (i+1,j), (i+1,j+1), (i,j+1)
};

struct SheetVertexSource {
  SheetVertexKind kind = SheetVertexKind::particle;
  std::uint32_t index = 0;   // particle, connector or cell, by kind
  std::uint8_t side = 0;     // connector_end: which end's half
  std::uint8_t corners = 0;  // cell_centre: the corners of the component, 4 bits (see above)
  bool operator==(const SheetVertexSource&) const = default;
};

// Corners of a lattice cell in the order of SheetVertexSource::corners, counter-clockwise seen
// from +y at rest: (i,j), (i+1,j), (i+1,j+1), (i,j+1). Edge k of the cell joins corner k and
// corner k+1 (mod 4).
inline constexpr std::array<std::array<int, 2>, 4> kCellCorners = {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};

// A triangle mesh of the sheet in one of the two modes.
struct SheetMesh {
  int grid_rows = 0;  // the grid: its vertex (i, j) is i*grid_cols + j
  int grid_cols = 0;
  std::vector<Vec3> vertex_position;                            // [vertices], m; the grid's first, then split vertices
  std::vector<Vec3> vertex_normal;                              // [vertices], unit
  std::vector<std::array<std::uint32_t, 3>> triangle_vertices;  // [triangles]; intact: 2 (grid_rows-1) (grid_cols-1)
  std::vector<SheetVertexSource> vertex_source;                 // [vertices]: what each vertex is
  // Counts the rebuilds of the topology (vertex_source, triangle_vertices): a renderer re-uploads
  // its index buffer when this moves.
  std::uint64_t topology_version = 0;

  // What the topology was built for, and its scratch (build_sheet_mesh's, not for callers).
  SheetMeshMode built_mode = SheetMeshMode::particles;
  int built_rows = -1;
  int built_cols = -1;
  std::size_t built_connectors = 0;
  bool built_torn = false;
  std::vector<std::uint8_t> built_live;                 // [connectors] the live mask of a torn build
  std::vector<std::array<std::uint32_t, 4>> cell_edge;  // [cells] connector of each cell edge, or kNoEdge

  static constexpr std::uint32_t kNoEdge = 0xFFFFFFFFu;
  std::size_t vertex_count() const { return vertex_position.size(); }
  // The bytes of the mesh of an intact rows x cols lattice in particles mode: a vertex (position,
  // normal, source) per particle and 2 triangles per cell (the memory estimate,
  // sim/memory_estimate.h; a torn sheet has a few more vertices and triangles).
  static constexpr std::size_t bytes_for(std::size_t rows, std::size_t cols) {
    const std::size_t cells = rows > 0 && cols > 0 ? (rows - 1) * (cols - 1) : 0;
    return rows * cols * (2 * sizeof(Vec3) + sizeof(SheetVertexSource)) +
           2 * cells * sizeof(std::array<std::uint32_t, 3>);
  }
};

// Rest-lattice coordinates (row, col) of a mesh vertex, in particle spacings: particle (i, j) is
// (i, j), a connector's midpoint or half (a broken connector's halves meet there at rest) is
// the mean of its ends', a cell centre is (i + 1/2, j + 1/2). io/obj's texture coordinates.
std::array<double, 2> sheet_vertex_lattice_coordinate(const ClothModel& model, const SheetVertexSource& source);

// Cell-centre positions [(rows-1) * (cols-1)]: cell (i, j) at the mean of particles (i, j),
// (i, j+1), (i+1, j), (i+1, j+1) of `position` [particle_count()].
std::vector<Vec3> cell_centre_positions(const ClothModel& model, std::span<const Vec3> position);

// The mesh of the sheet at `position` [particle_count()] in `mode`, split along the model's
// broken connectors (see the top of this file). `mesh` is reused: its topology is rebuilt only
// when the grid, the mode or the set of broken connectors changes, so calling this every frame
// allocates nothing after the first call until the next break.
void build_sheet_mesh(const ClothModel& model, std::span<const Vec3> position, SheetMeshMode mode, SheetMesh& mesh);

}  // namespace clothsim
