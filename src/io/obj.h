// Wavefront OBJ snapshots of the sheet, and the triangle mesh behind them.
//
// The mesh (triangulation, winding, vertex normals, splitting along tears) is
// model/sheet_mesh.h's particle-mode mesh.
//
// The OBJ file has one v, vt and vn line per mesh vertex, so a face corner's v/vt/vn indices are
// all vertex index + 1. The first rows*cols vertices are the particles in particle order; a torn
// sheet's split vertices (connector midpoints and halves, quad centres) follow, and a second
// comment line says how many there are. A 1-wide lattice (rows == 1 or cols == 1) has no faces
// and is written as a polyline (`l`), one per piece when connectors are broken.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/vec3.h"
#include "model/cloth_model.h"
#include "model/sheet_mesh.h"

namespace clothsim {

// Writes the sheet at `position` [particle_count()], m, to `path` (created or truncated):
// comment lines (a clothsim line, for a torn sheet a line counting its vertices, then `comment`
// split at '\n'), `o clothsim_sheet`, then v, vt (u = col/(cols-1), v = row/(rows-1) of the
// vertex's rest-lattice coordinates; 0 along a 1-wide axis) and vn per vertex, `s 1` and
// `f v/vt/vn` triangles, or `l` for a 1-wide lattice. Coordinates are written with 9 significant
// digits (round-trip precision for float, what renderers load). Throws std::runtime_error naming
// the path and the reason on a size mismatch or an I/O failure; a failed write may leave a
// partial file.
void write_obj(const std::string& path, const ClothModel& model, std::span<const Vec3> position,
               std::string_view comment = {});

// Writes a mesh of the sheet built elsewhere (vertex positions, normals, sources and triangles of
// `mesh`, e.g. a run's rest.obj, run/run_exports.h), in the same layout as write_obj. A 1-wide
// lattice is written as write_obj writes it, a polyline through the particles.
void write_obj_mesh(const std::string& path, const ClothModel& model, const SheetMesh& mesh,
                    std::string_view comment = {});

}  // namespace clothsim
