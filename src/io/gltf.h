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
// Every accessor carries its min and max (the spec requires them of POSITION only; viewers use
// them for bounds, validators check them).
//
// animation.glb (write_glb_animation) is the whole run in one file, docs/exports.md: the same
// document with the first frame as the base mesh, one morph target per frame (the displacement
// of every vertex's position and normal from the base), and one animation whose LINEAR "weights"
// channel has a keyframe at every frame's time with weight 1 on that frame's target and 0 on
// the others, so that the mesh at frame k is frame k and between two frames their linear blend.
// The mesh is the model's topology (a torn sheet's split along the tears of its last frame)
// placed at every frame's particle positions. Rejected: a node per frame whose scale switches
// it on (STEP): no blend between frames, and the index and texture arrays repeated every frame;
// sparse weight accessors: smaller for long runs, but not every importer reads sparse animation
// outputs. Normals are morphed too, so that shading follows the motion in viewers that take the
// normals from the file (three.js does; Blender recomputes them).
//
// The file is written in two passes over the frames, read one at a time through a callback (the
// run reads them back from positions.npy): the first for the targets' bounds, which the JSON
// chunk holds and which comes first, the second for the arrays. So it holds one frame and one
// mesh at a time, however long the run. The JSON is tinygltf's, of the document less its buffer;
// the GLB container around it is written here, streaming the binary chunk.
//
// Written with tinygltf (Debian's libtinygltf-dev), compiled into gltf.cpp alone: see there.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
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

// What animation.glb holds besides the frames: frame k is at t = k / fps.
struct GlbAnimation {
  std::string scene;  // the scene's name: the node's extras, the animation's name
  std::size_t frames = 0;
  double fps = 60.0;  // frames per second of simulated time
};

// Reads frame `frame` (0 to frames - 1) of the run into `position` [particle_count()], m.
using GlbFrameReader = std::function<void(std::size_t frame, std::span<Vec3> position)>;

// Writes `animation.frames` frames of the sheet of `model` (its topology for every frame), read
// through `read_frame` twice each, to `path` (created or truncated) as animation.glb (above).
// Throws std::runtime_error naming the path on a file over GLB's 4 GiB or an I/O failure (or
// what `read_frame` throws); a failed write may leave a partial file.
GlbCounts write_glb_animation(const std::string& path, const ClothModel& model, const GlbAnimation& animation,
                              const GlbFrameReader& read_frame);

// The most memory write_glb_animation holds for `frames` frames of an intact rows x cols
// lattice: final.glb's (the base mesh's document), a second mesh, a frame's positions and its
// displacements, and about 7 kB a frame of document (each target's accessors, buffer views and
// name, as tinygltf's structures, then as its JSON tree and text; measured 6.7 kB a frame with
// 1723 frames of paper-fig5: counted as 8 kB).
std::size_t glb_animation_memory_for(std::size_t rows, std::size_t cols, std::size_t frames);

// The size of animation.glb for `frames` frames of an intact rows x cols lattice, bytes
// (docs/exports.md): 24 bytes a vertex and frame (12 for a 1-wide lattice, which has no normals),
// 4 F^2 for the weights, the JSON's few hundred bytes a frame and the base mesh. A torn sheet's
// split vertices add to it.
std::uint64_t glb_animation_bytes_for(std::size_t rows, std::size_t cols, std::size_t frames);

}  // namespace clothsim
