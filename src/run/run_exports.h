// The files a run writes for other tools, chosen by the scene's output.export (docs/exports.md):
//   pc2           animation.pc2, a PC2 point cache (io/pc2.h) of the particles at every frame the
//                 run saves (the frames of positions.npy), and rest.obj, the mesh it deforms
//   obj-sequence  frames/frame_000000.obj and on, the sheet at every saved frame (io/obj.h)
//   gltf          final.glb, the last frame as binary glTF (io/gltf.h): the mesh of final.obj,
//                 written by finish() like final.obj, so a resumed run writes it at its end too
//   gltf-animation  animation.glb, every saved frame in one binary glTF (io/gltf.h): written by
//                 finish() from positions.npy, which holds every frame and is closed by then, rather
//                 than kept in memory (a long run of a large sheet does not fit) or streamed to a
//                 file of its own (a second copy of the trajectory). A resumed run's positions.npy is
//                 the uninterrupted run's, so its animation.glb is too. Its size grows with the
//                 frames times the vertices, and with the frames squared (the weights): a run whose
//                 file would pass kAnimationGlbLimit is refused before it starts (check_sizes).
//
// The cache starts at frame 0 with one sample per frame, so in Blender cache frame k is the
// run's frame k, at t = k / output.fps; set the Blender scene's frame rate to output.fps.
//
// Torn sheets. A point cache has one vertex set for the whole run, but a tearing sheet's mesh
// gains vertices at every break (model/sheet_mesh.h splits it along broken connectors). So the
// cache's points are always the particles, in index order, and rest.obj is a mesh of the
// particles alone: the lattice triangles, less every triangle with an edge whose connector is
// broken by the end of the run. No face then ever spans a tear, at the price of showing the
// tear's gap (about one lattice cell wide) from the first frame on. The exact split mesh of every
// frame is the obj-sequence's. Rejected: faces of the initial sheet (they stretch across every
// tear like rubber, hiding that it tore), refusing pc2 for sheets that can tear (most material
// presets can), and caching the final split mesh's vertices (not known until the run ends, so
// the cache could not be streamed).
//
// rest.obj's vertices are the particles at frame 0, so that opening it alone shows the first
// frame; it is written at the end, when the run's broken connectors are known.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/vec3.h"
#include "io/gltf.h"
#include "io/pc2.h"
#include "model/cloth_model.h"
#include "model/sheet_mesh.h"
#include "scene/scene.h"

namespace clothsim {

class RunExports {
 public:
  static constexpr std::string_view kPointCacheFile = "animation.pc2";
  static constexpr std::string_view kRestMeshFile = "rest.obj";
  static constexpr std::string_view kFramesFolder = "frames";
  static constexpr std::string_view kGlbFile = "final.glb";
  static constexpr std::string_view kAnimationGlbFile = "animation.glb";
  // The largest animation.glb a run may plan, bytes: half of GLB's 4 GiB, whose 32-bit lengths
  // are a hard limit, because the estimate counts an intact sheet (a torn one's split vertices
  // add to it) and because viewers hold the file whole: browsers cap an ArrayBuffer near 2 GiB,
  // and Blender's importer decodes every target into memory. docs/exports.md.
  static constexpr std::uint64_t kAnimationGlbLimit = std::uint64_t{2} << 30;

  // Creates the files of `formats` in `folder` (a run's partial folder) for a sheet of `model`.
  // Throws std::runtime_error naming the path on an I/O failure.
  RunExports(std::filesystem::path folder, std::span<const ExportFormat> formats, const ClothModel& model,
             std::string scene_name);
  // Takes over the files of `formats` in `folder`, written up to `frames` frames by a run resumed
  // from a checkpoint (run/run_checkpoints.h): cuts off what came after them and goes on from
  // frame `frames`. `first_position` is frame 0 (rest.obj's vertices). Throws std::runtime_error.
  RunExports(std::filesystem::path folder, std::span<const ExportFormat> formats, const ClothModel& model,
             std::string scene_name, std::size_t frames, std::span<const Vec3> first_position);

  // Writes the sheet at `position` [particle_count()], m, time `time`, s, as the next frame
  // (frame 0 first: the initial state).
  void write_frame(const ClothModel& model, std::span<const Vec3> position, double time);

  // Hands the cache's buffered samples to the operating system (the OBJ files are whole already).
  void flush() {
    if (cache_) cache_->flush();
  }
  // Closes the cache and writes rest.obj from the model's final broken connectors, final.glb
  // of `last_position` [particle_count()], m, the last frame written, at `last_time`, s, and
  // animation.glb of every frame of `positions` (positions.npy, closed), frame k at k / fps.
  void finish(const ClothModel& model, std::span<const Vec3> last_position, double last_time,
              const std::filesystem::path& positions, int fps);

  // summary.json "files" entries for what finish() left: name and details.
  std::vector<std::pair<std::string, nlohmann::ordered_json>> summary_files() const;

  // "frames/frame_000042.obj".
  static std::string frame_file_name(std::size_t frame);

  // Memory for `frames` frames of the lattice of `counts` writing `formats`: held from the first
  // frame to the end (the cache's frame buffer and frame 0's positions), and the most held for a
  // moment (a frame's mesh, rest.obj's mesh, animation.glb's writer) (run/run_memory.h).
  struct Memory {
    std::size_t held = 0;
    std::size_t peak = 0;
  };
  static Memory bytes_for(const LatticeCounts& counts, std::size_t frames, std::span<const ExportFormat> formats);

  // Refuses, before the run, exports that would pass their size limit for `frames` frames of the
  // lattice of `counts`: animation.glb above kAnimationGlbLimit. Throws InputError naming
  // output.export, the estimate, the limit and what to change.
  static void check_sizes(const LatticeCounts& counts, std::size_t frames, std::span<const ExportFormat> formats);

 private:
  std::filesystem::path folder_;
  std::string scene_name_;
  std::size_t points_ = 0;  // of the cache: the particles
  bool obj_sequence_ = false;
  bool gltf_ = false;
  bool gltf_animation_ = false;
  std::optional<Pc2Writer> cache_;
  std::vector<Vec3> first_position_;  // [particles], m: frame 0, rest.obj's vertices
  std::size_t frames_ = 0;
  std::size_t rest_triangles_ = 0;          // written to rest.obj
  std::size_t dropped_triangles_ = 0;       // left out of rest.obj: they span a broken connector
  std::optional<GlbCounts> glb_;            // what final.glb holds, once written
  std::optional<GlbCounts> animation_glb_;  // what animation.glb holds, once written
  int fps_ = 0;                             // animation.glb's
};

// Lattice triangles (model/sheet_mesh.h) none of whose edges is a broken connector of `model`:
// rest.obj's faces.
std::vector<std::array<std::uint32_t, 3>> intact_lattice_triangles(const ClothModel& model);

}  // namespace clothsim
