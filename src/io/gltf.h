// Binary glTF 2.0 (.glb) snapshots of the sheet: one mesh, one node, one scene, for Blender, three.js,
// game engines and anything else that reads glTF (docs/exports.md).
//
// The mesh is final.obj's (io/obj.h, model/sheet_mesh.h's particle-mode mesh): the same vertices
// in the same order (the particles first, a torn sheet's split vertices after them), the same
// triangles with the same winding, the same vertex normals. One primitive holds
//   POSITION    float32 VEC3, m, with the accessor's min and max (the spec requires them);
//   NORMAL      float32 VEC3, unit;
//   TEXCOORD_0  float32 VEC2: (col / (cols-1), 1 - row / (rows-1)) of the vertex's rest-lattice
//               coordinates. glTF puts the texture's origin at its top left and OBJ at its bottom
//               left, so v is flipped to put an image on the sheet the way final.obj does;
//   indices     uint32 SCALAR, 3 per triangle.
// Coordinates are clothsim's as they are: metres, y up, which is what glTF specifies, so no
// conversion (Blender's importer turns y up into its z up itself). A 1-wide lattice (rows == 1 or
// cols == 1) has no faces: it is written as LINES along its intact connectors (as the OBJ's
// polyline), without normals, or as POINTS when none is left.
//
// The material is double-sided (a sheet has two sides, and its triangles face only one way),
// metallic 0, roughness 0.9, with the base colour of the renderer's front side (docs/rendering.md)
// in linear RGB. The node carries the scene name, frame and time as extras (Blender shows them as
// custom properties of the object).
//
// The file is one GLB: a 12-byte header, the JSON chunk and one binary chunk with the four arrays
// back to back (all 4-byte aligned). GLB's lengths are 32-bit, so a mesh whose arrays pass 4 GiB
// (far beyond a 4096 x 4096 sheet) is refused with an error rather than written wrong.
//
// Written with tinygltf (Debian's libtinygltf-dev), compiled into gltf.cpp alone: see there.
#pragma once

#include <cstddef>
#include <span>
#include <string>

#include "core/vec3.h"
#include "model/cloth_model.h"

namespace clothsim {

// What the node's extras say about the snapshot.
struct GlbFrame {
  std::string scene;  // the scene's name
  std::size_t frame = 0;
  double time = 0.0;  // s
};

// What write_glb wrote.
struct GlbCounts {
  std::size_t vertices = 0;
  std::size_t triangles = 0;  // 0 for a 1-wide lattice (lines or points)
};

// Writes the sheet at `position` [particle_count()], m, to `path` (created or truncated) as binary
// glTF. Throws std::runtime_error naming the path and the reason on a size mismatch, a mesh too
// large for GLB or an I/O failure; a failed write may leave a partial file.
GlbCounts write_glb(const std::string& path, const ClothModel& model, std::span<const Vec3> position,
                    const GlbFrame& frame = {});

// The most memory write_glb holds for an intact rows x cols lattice: the mesh (SheetMesh::bytes_for)
// and its arrays twice (tinygltf's buffer, and its copy into the file's binary chunk).
std::size_t glb_bytes_for(std::size_t rows, std::size_t cols);

}  // namespace clothsim
