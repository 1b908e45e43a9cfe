// Wavefront OBJ snapshots of the sheet, and the triangle mesh behind them.
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
// The OBJ file has one v, vt and vn line per particle, in particle order, so a face corner's
// v/vt/vn indices are all particle index + 1. Vertex normals are area-weighted means of the face
// normals (the unnormalised cross product of a triangle is twice its area times its normal),
// which weights large faces more and needs no angle computations. A 1-wide lattice (rows == 1 or
// cols == 1) has no faces and is written as a polyline (`l`).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/vec3.h"
#include "model/cloth_model.h"

namespace clothsim {

// Triangles of the lattice, particle indices wound as above: [2 (rows-1) (cols-1)], empty for a
// 1-wide lattice. Quad (i, j) owns triangles 2 (i (cols-1) + j) and 2 (i (cols-1) + j) + 1.
std::vector<std::array<std::uint32_t, 3>> lattice_triangles(const ClothModel& model);

// Unit vertex normals [particle_count()] of the mesh `triangles` at `position`
// [particle_count()], m: the area-weighted mean of the incident face normals. A particle with no
// incident area (no faces, or all degenerate, or a non-finite sum) gets (0, 1, 0), the rest
// lattice's normal, so renderers never see a NaN.
std::vector<Vec3> vertex_normals(const ClothModel& model, std::span<const Vec3> position,
                                 std::span<const std::array<std::uint32_t, 3>> triangles);

// Writes the sheet at `position` [particle_count()], m, to `path` (created or truncated):
// comment lines (a clothsim line, then `comment` split at '\n'), `o clothsim_sheet`, then v, vt
// (u = col/(cols-1), v = row/(rows-1); 0 along a 1-wide axis) and vn per particle, `s 1` and
// `f v/vt/vn` triangles, or `l` for a 1-wide lattice. Coordinates are written with 9 significant
// digits (round-trip precision for float, what renderers load). Throws std::runtime_error naming
// the path and the reason on a size mismatch or an I/O failure; a failed write may leave a
// partial file.
void write_obj(const std::string& path, const ClothModel& model, std::span<const Vec3> position,
               std::string_view comment = {});

}  // namespace clothsim
