// A binary glTF file (final.glb, io/gltf.h) as the tests see it, read by tinygltf's own loader
// (TinyGLTF::LoadBinaryFromFile): compiled in glb_reader.cpp, apart from the library's copy, which
// lives in a namespace of its own (src/io/gltf.cpp), so the tests read the file with a loader that
// shares no state with the writer. Used by tests/io and tests/apps.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace clothsim::testing {

// The one mesh primitive of a clothsim GLB, its arrays decoded.
struct GlbMesh {
  bool loaded = false;
  std::string error;  // the loader's error and warning text, or what the checks below found
  std::string version;
  std::size_t scenes = 0, nodes = 0, meshes = 0, primitives = 0, materials = 0;
  int default_scene = -1;
  int mode = -1;  // 4 triangles, 1 lines, 0 points (TINYGLTF_MODE_*)
  bool double_sided = false;
  std::vector<float> position;  // [vertices * 3], m
  std::vector<float> normal;    // [vertices * 3], empty when the primitive has none
  std::vector<float> uv;        // [vertices * 2]
  std::vector<std::uint32_t> index;
  std::vector<double> position_min, position_max;  // the POSITION accessor's min and max
  double extras_time = -1.0;                       // the node's extras "time", s
  int extras_frame = -1;                           // the node's extras "frame"

  // Morph targets and animation (animation.glb).
  std::size_t accessors = 0;
  std::size_t accessors_without_bounds = 0;         // accessors lacking min or max
  std::size_t non_float_accessors = 0;              // accessors other than float32, uint32 indices aside
  std::vector<std::vector<float>> target_position;  // [targets][vertices * 3], m: POSITION displacements
  std::vector<std::vector<float>> target_normal;    // [targets][vertices * 3]: NORMAL displacements
  std::vector<double> mesh_weights;                 // the mesh's default weights
  std::size_t animations = 0;
  std::size_t channels = 0;                                    // of the first animation
  int channel_node = -1;                                       // its first channel's
  std::string channel_path;                                    // "weights"
  std::string interpolation;                                   // its sampler's
  std::vector<float> animation_time;                           // the sampler's input, s
  std::vector<float> animation_weight;                         // the sampler's output [times * targets]
  std::vector<double> animation_time_min, animation_time_max;  // the input accessor's bounds

  std::size_t vertices() const { return position.size() / 3; }
};

// Loads `path` and decodes the first mesh's first primitive, its morph targets and the first
// animation's first channel; `loaded` false (and `error`) when the loader refuses the file or the
// primitive lacks POSITION, TEXCOORD_0 or indices, or a target or the animation cannot be read.
GlbMesh read_glb(const std::filesystem::path& path);

}  // namespace clothsim::testing
