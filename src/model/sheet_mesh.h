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
// Every quad is cut along the same diagonal. Alternating diagonals would make the mesh symmetric
// under mirroring, but the mesh is used only for output and rendering (the physics has no
// triangles), where a uniform cut is simpler and indistinguishable.
//
// Two ways to place the mesh's vertices (SheetMeshMode):
//   particles     one vertex per particle, at the particle: the default. Anchors and edges are
//                 where the physics has them.
//   cell_centres  the paper's rendering: one vertex per lattice cell, at the mean of its 4
//                 corner particles, so a rows x cols lattice shows (rows-1) x (cols-1) vertices
//                 (the paper, section 3). The sheet looks half a cell smaller on every side and
//                 an anchored particle is no vertex of it; kept to reproduce the paper's figures.
// Cell (i, j) of the cell-centre mesh plays the role of particle (i, j) of a (rows-1) x (cols-1)
// lattice, so both modes share the triangulation code.
//
// Vertex normals are area-weighted means of the face normals (the unnormalised cross product of
// a triangle is twice its area times its normal), which weights large faces more and needs no
// angle computations.
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
std::vector<Vec3> vertex_normals(std::span<const Vec3> position, std::span<const std::array<std::uint32_t, 3>> triangles);
// The same, for particle positions of `model` [particle_count()].
std::vector<Vec3> vertex_normals(const ClothModel& model, std::span<const Vec3> position,
                                 std::span<const std::array<std::uint32_t, 3>> triangles);

// Grid size of the mesh in `mode`: {rows, cols} or {rows-1, cols-1} (0 where a side is 1).
std::array<int, 2> sheet_mesh_grid(const ClothModel& model, SheetMeshMode mode);

// A triangle mesh of the sheet in one of the two modes.
struct SheetMesh {
  int grid_rows = 0;                                   // vertex grid: vertex (i, j) is i*grid_cols + j
  int grid_cols = 0;
  std::vector<Vec3> vertex_position;                   // [grid_rows * grid_cols], m
  std::vector<Vec3> vertex_normal;                     // [grid_rows * grid_cols], unit
  std::vector<std::array<std::uint32_t, 3>> triangle_vertices;  // [2 (grid_rows-1) (grid_cols-1)]
};

// Cell-centre positions [(rows-1) * (cols-1)]: cell (i, j) at the mean of particles (i, j),
// (i, j+1), (i+1, j), (i+1, j+1) of `position` [particle_count()].
std::vector<Vec3> cell_centre_positions(const ClothModel& model, std::span<const Vec3> position);

// The mesh of the sheet at `position` [particle_count()] in `mode`. `mesh` is reused: its
// triangles are rebuilt only when the grid changes, so calling this every frame allocates nothing
// after the first call.
void build_sheet_mesh(const ClothModel& model, std::span<const Vec3> position, SheetMeshMode mode, SheetMesh& mesh);

}  // namespace clothsim
