// The exports of a run; what they hold and the rule for torn sheets are in run_exports.h.
#include "run/run_exports.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <system_error>

#include "core/error.h"
#include "io/npy.h"
#include "io/obj.h"

namespace clothsim {
namespace {

namespace fs = std::filesystem;

std::string frame_comment(const std::string& scene_name, std::size_t frame, double time) {
  std::array<char, 64> seconds{};
  std::snprintf(seconds.data(), seconds.size(), "%.9g", time);
  return "scene " + scene_name + ", frame " + std::to_string(frame) + " at t = " + seconds.data() + " s";
}

}  // namespace

std::vector<std::array<std::uint32_t, 3>> intact_lattice_triangles(const ClothModel& model) {
  // broken_right[p]: the connector from p to its right neighbour is broken; broken_down[p]: to
  // the particle below. Connectors join 4-neighbours only.
  const std::size_t n = model.particle_count();
  const std::uint32_t cols = static_cast<std::uint32_t>(model.cols);
  std::vector<std::uint8_t> broken_right(n, 0);
  std::vector<std::uint8_t> broken_down(n, 0);
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    if (model.connector_live[e] != 0) continue;
    const auto [a, b] = model.connector_particles[e];
    const std::uint32_t first = std::min(a, b);
    (std::max(a, b) == first + cols ? broken_down : broken_right)[first] = 1;
  }
  // An edge (u, v), u < v, of a lattice triangle is a connector when v is u's right or lower
  // neighbour; the triangle's third edge is a quad diagonal, which no spring follows.
  const auto edge_broken = [&](std::uint32_t u, std::uint32_t v) {
    if (u > v) std::swap(u, v);
    if (v == u + cols) return broken_down[u] != 0;
    if (v == u + 1 && u % cols != cols - 1) return broken_right[u] != 0;
    return false;
  };
  std::vector<std::array<std::uint32_t, 3>> triangles;
  for (const auto& triangle : lattice_triangles(model)) {
    const auto [a, b, c] = triangle;
    if (!edge_broken(a, b) && !edge_broken(b, c) && !edge_broken(c, a)) triangles.push_back(triangle);
  }
  return triangles;
}

std::string RunExports::frame_file_name(std::size_t frame) {
  std::array<char, 32> name{};
  std::snprintf(name.data(), name.size(), "frame_%06zu.obj", frame);
  return std::string(kFramesFolder) + "/" + name.data();
}

RunExports::RunExports(fs::path folder, std::span<const ExportFormat> formats, const ClothModel& model,
                       std::string scene_name)
    : folder_(std::move(folder)), scene_name_(std::move(scene_name)), points_(model.particle_count()) {
  for (ExportFormat format : formats) {
    if (format == ExportFormat::pc2) {
      // Frame 0 first, one sample per saved frame: cache frame k is the run's frame k.
      cache_.emplace((folder_ / kPointCacheFile).string(), model.particle_count(), 0.0f, 1.0f);
    } else if (format == ExportFormat::obj_sequence) {
      obj_sequence_ = true;
      fs::create_directory(folder_ / kFramesFolder);
    } else if (format == ExportFormat::gltf) {
      gltf_ = true;  // written by finish()
    } else if (format == ExportFormat::gltf_animation) {
      gltf_animation_ = true;  // written by finish(), from positions.npy
    }
  }
}

RunExports::RunExports(fs::path folder, std::span<const ExportFormat> formats, const ClothModel& model,
                       std::string scene_name, std::size_t frames, std::span<const Vec3> first_position)
    : folder_(std::move(folder)), scene_name_(std::move(scene_name)), points_(model.particle_count()), frames_(frames) {
  for (ExportFormat format : formats) {
    if (format == ExportFormat::pc2) {
      cache_.emplace((folder_ / kPointCacheFile).string(), model.particle_count(), frames);
      first_position_.assign(first_position.begin(), first_position.end());
    } else if (format == ExportFormat::obj_sequence) {
      obj_sequence_ = true;
      fs::create_directories(folder_ / kFramesFolder);
      // Frames past the checkpoint's, which the resumed run writes again.
      for (std::size_t frame = frames;; ++frame) {
        std::error_code error;
        if (!fs::remove(folder_ / frame_file_name(frame), error)) break;
      }
    } else if (format == ExportFormat::gltf) {
      gltf_ = true;  // RunWriter::resume removed a finished run's final.glb; finish() writes it
    } else if (format == ExportFormat::gltf_animation) {
      gltf_animation_ = true;  // likewise animation.glb, from the whole positions.npy
    }
  }
}

RunExports::Memory RunExports::bytes_for(const LatticeCounts& counts, std::size_t frames,
                                         std::span<const ExportFormat> formats) {
  Memory memory;
  const std::size_t mesh = SheetMesh::bytes_for(counts.rows, counts.cols);
  for (ExportFormat format : formats) {
    if (format == ExportFormat::pc2) {
      // A float32 sample per particle, frame 0's positions; at the end rest.obj's mesh and the
      // lattice's triangles it is cut from.
      memory.held += counts.particles * (3 * sizeof(float) + sizeof(Vec3));
      const std::size_t cells = counts.rows > 0 && counts.cols > 0 ? (counts.rows - 1) * (counts.cols - 1) : 0;
      memory.peak = std::max(memory.peak, mesh + 2 * cells * sizeof(std::array<std::uint32_t, 3>));
    } else if (format == ExportFormat::obj_sequence) {
      memory.peak = std::max(memory.peak, mesh);  // each frame's mesh
    } else if (format == ExportFormat::gltf) {
      memory.peak = std::max(memory.peak, glb_bytes_for(counts.rows, counts.cols));  // at the end
    } else if (format == ExportFormat::gltf_animation) {
      memory.peak = std::max(memory.peak, glb_animation_memory_for(counts.rows, counts.cols, frames));  // at the end
    }
  }
  return memory;
}

void RunExports::write_frame(const ClothModel& model, std::span<const Vec3> position, double time) {
  if (cache_) {
    cache_->append(position);
    if (frames_ == 0) first_position_.assign(position.begin(), position.end());
  }
  if (obj_sequence_) {
    const std::string path = (folder_ / frame_file_name(frames_)).string();
    write_obj(path, model, position, frame_comment(scene_name_, frames_, time));
  }
  ++frames_;
}

void RunExports::check_sizes(const LatticeCounts& counts, std::size_t frames, std::span<const ExportFormat> formats) {
  if (std::find(formats.begin(), formats.end(), ExportFormat::gltf_animation) == formats.end()) return;
  const std::uint64_t bytes = glb_animation_bytes_for(counts.rows, counts.cols, frames);
  if (bytes <= kAnimationGlbLimit) return;
  const auto mib = [](std::uint64_t value) { return std::to_string((value + (1u << 20) - 1) >> 20) + " MiB"; };
  throw InputError("", "output.export",
                   "gltf-animation: " + std::string(kAnimationGlbFile) + " of " + std::to_string(frames) +
                       " frames of " + std::to_string(counts.particles) + " particles would take about " + mib(bytes) +
                       ", more than its limit of " + mib(kAnimationGlbLimit) +
                       " (docs/exports.md: about 24 bytes a particle and frame, plus 4 bytes per frame squared); "
                       "use fewer frames (a shorter --duration or a lower --fps) or a smaller sheet, or --export pc2 "
                       "for a point cache of any length");
}

void RunExports::finish(const ClothModel& model, std::span<const Vec3> last_position, double last_time,
                        const std::filesystem::path& positions, int fps) {
  if (gltf_ && frames_ > 0) {
    glb_ =
        write_glb((folder_ / kGlbFile).string(), model, last_position, GlbFrame{scene_name_, frames_ - 1, last_time});
  }
  if (gltf_animation_ && frames_ > 0) {
    fps_ = fps;
    const std::string positions_file = positions.string();
    animation_glb_ = write_glb_animation((folder_ / kAnimationGlbFile).string(), model,
                                         GlbAnimation{scene_name_, frames_, static_cast<double>(fps)},
                                         [&positions_file](std::size_t frame, std::span<Vec3> position) {
                                           read_npy_frame(positions_file, frame, position);
                                         });
  }
  if (!cache_) return;
  cache_->close();
  if (first_position_.empty()) return;  // no frame: no mesh to deform
  SheetMesh mesh;
  mesh.grid_rows = model.rows;
  mesh.grid_cols = model.cols;
  mesh.vertex_position = first_position_;
  mesh.vertex_source.resize(first_position_.size());
  for (std::size_t p = 0; p < mesh.vertex_source.size(); ++p) {
    mesh.vertex_source[p] = SheetVertexSource{SheetVertexKind::particle, static_cast<std::uint32_t>(p)};
  }
  mesh.triangle_vertices = intact_lattice_triangles(model);
  mesh.vertex_normal = vertex_normals(mesh.vertex_position, mesh.triangle_vertices);
  rest_triangles_ = mesh.triangle_vertices.size();
  dropped_triangles_ = lattice_triangles(model).size() - rest_triangles_;
  std::string comment = "the mesh of " + std::string(kPointCacheFile);
  comment += ": its vertices are the particles in index order, at frame 0";
  if (dropped_triangles_ > 0) {
    comment += "\nleft out: " + std::to_string(dropped_triangles_) +
               " triangles across connectors broken during the run (docs/exports.md)";
  }
  write_obj_mesh((folder_ / kRestMeshFile).string(), model, mesh, comment);
}

std::vector<std::pair<std::string, nlohmann::ordered_json>> RunExports::summary_files() const {
  using ordered_json = nlohmann::ordered_json;
  std::vector<std::pair<std::string, ordered_json>> files;
  if (cache_) {
    files.emplace_back(std::string(kPointCacheFile), ordered_json{{"format", "pc2"},
                                                                  {"points", points_},
                                                                  {"samples", cache_->samples()},
                                                                  {"start_frame", 0},
                                                                  {"sample_rate", 1},
                                                                  {"dtype", "float32"},
                                                                  {"unit", "m"},
                                                                  {"mesh", std::string(kRestMeshFile)}});
    files.emplace_back(std::string(kRestMeshFile),
                       ordered_json{{"frame", 0}, {"triangles", rest_triangles_}, {"left_out", dropped_triangles_}});
  }
  if (obj_sequence_) {
    files.emplace_back(std::string(kFramesFolder) + "/",
                       ordered_json{{"format", "obj-sequence"}, {"files", frames_}, {"first", frame_file_name(0)}});
  }
  if (glb_) {
    files.emplace_back(std::string(kGlbFile), ordered_json{{"format", "gltf"},
                                                           {"frame", frames_ - 1},
                                                           {"vertices", glb_->vertices},
                                                           {"triangles", glb_->triangles},
                                                           {"unit", "m"},
                                                           {"up", "+y"}});
  }
  if (animation_glb_) {
    files.emplace_back(std::string(kAnimationGlbFile), ordered_json{{"format", "gltf-animation"},
                                                                    {"frames", frames_},
                                                                    {"fps", fps_},
                                                                    {"morph_targets", frames_},
                                                                    {"vertices", animation_glb_->vertices},
                                                                    {"triangles", animation_glb_->triangles},
                                                                    {"unit", "m"},
                                                                    {"up", "+y"}});
  }
  return files;
}

}  // namespace clothsim
