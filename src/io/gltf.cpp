// The GLB writer; what the file holds is in gltf.h, the mesh in model/sheet_mesh.h.
//
// tinygltf. Debian's libtinygltf-dev ships the header and a shared libtinygltf.so built with stb
// image support. clothsim compiles the implementation here instead, once (TINYGLTF_IMPLEMENTATION
// in this file and nowhere else), with image support left out (TINYGLTF_NO_STB_IMAGE, ..._WRITE,
// ..._EXTERNAL_IMAGE: the file has no images), so the library needs neither stb nor the shared
// library, and any system with tiny_gltf.h and nlohmann/json.hpp builds it. Its namespace is
// renamed to clothsim_tinygltf for this file: clothsim's libraries are static and installable
// (docs/library.md), and a program that links them and has a tinygltf of its own (another
// version, its own TINYGLTF_IMPLEMENTATION, Debian's libtinygltf.so) would otherwise get two
// definitions of every tinygltf function. The header is a system header, so -Werror does not
// apply to it. Rejected: linking Debian's libtinygltf.so (simplest, but the installed
// library would then need it, and stb, on every machine that links clothsim).
//
// The file goes through WriteGltfSceneToStream into a stream of our own, not
// WriteGltfSceneToFile, which does not check its writes: a full disk would pass silently.
#include "io/gltf.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <climits>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "io/file_writing.h"
#include "model/sheet_mesh.h"

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define tinygltf clothsim_tinygltf
#include <tiny_gltf.h>
#undef tinygltf

namespace clothsim {
namespace {

namespace gltf = ::clothsim_tinygltf;

// The base colour of the renderer's front side (render/render_options.h, sRGB 0.85, 0.33, 0.18)
// in linear RGB, as glTF's baseColorFactor is.
constexpr std::array<double, 4> kSheetColour = {0.694, 0.089, 0.027, 1.0};

// Adds a buffer view of buffer 0 over [offset, offset + length) bytes; `target` ARRAY_BUFFER,
// ELEMENT_ARRAY_BUFFER or 0 (none: animation data). Returns its index.
int add_view(gltf::Model& file, std::size_t offset, std::size_t length, int target) {
  gltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = offset;
  view.byteLength = length;
  view.target = target;
  file.bufferViews.push_back(view);
  return static_cast<int>(file.bufferViews.size() - 1);
}

// Adds an accessor of `count` elements of `type` over the whole of buffer view `view`, with the
// per-component `low` and `high` (every accessor carries them, not only the POSITION ones the spec
// requires: viewers use them for bounds and validators check them). Returns its index.
int add_accessor(gltf::Model& file, int view, std::size_t count, int component_type, int type, std::vector<double> low,
                 std::vector<double> high) {
  gltf::Accessor accessor;
  accessor.bufferView = view;
  accessor.byteOffset = 0;
  accessor.componentType = component_type;
  accessor.count = count;
  accessor.type = type;
  accessor.minValues = std::move(low);
  accessor.maxValues = std::move(high);
  file.accessors.push_back(accessor);
  return static_cast<int>(file.accessors.size() - 1);
}

// The least and greatest of each of the `components` components of `values` (elements back to back).
template <typename T>
std::array<std::vector<double>, 2> component_bounds(std::span<const T> values, std::size_t components) {
  std::vector<double> low(components, std::numeric_limits<double>::infinity());
  std::vector<double> high(components, -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < values.size(); ++i) {
    low[i % components] = std::min(low[i % components], static_cast<double>(values[i]));
    high[i % components] = std::max(high[i % components], static_cast<double>(values[i]));
  }
  if (values.empty()) low = high = std::vector<double>(components, 0.0);
  return {low, high};
}

// Appends `values` to buffer 0 as a buffer view (`target` as add_view's) and an accessor of
// `components` components of `component_type` an element over it, with their bounds; returns the
// accessor's index.
template <typename T>
int add_array(gltf::Model& file, const std::vector<T>& values, std::size_t components, int component_type, int type,
              int target) {
  gltf::Buffer& buffer = file.buffers.front();
  const std::size_t offset = buffer.data.size();
  const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
  // A multiple of 4: every T here is 4 bytes.
  buffer.data.insert(buffer.data.end(), bytes, bytes + values.size() * sizeof(T));
  auto [low, high] = component_bounds(std::span<const T>(values), components);
  return add_accessor(file, add_view(file, offset, values.size() * sizeof(T), target), values.size() / components,
                      component_type, type, std::move(low), std::move(high));
}

// Clothsim's coordinates rounded to float32, 3 per value.
std::vector<float> to_float32(std::span<const Vec3> values) {
  std::vector<float> rounded(3 * values.size());
  for (std::size_t v = 0; v < values.size(); ++v) {
    rounded[3 * v] = static_cast<float>(values[v].x);
    rounded[3 * v + 1] = static_cast<float>(values[v].y);
    rounded[3 * v + 2] = static_cast<float>(values[v].z);
  }
  return rounded;
}

// GLB's lengths are 32-bit. The JSON chunk of final.glb is a few kB; `json_bytes` is the most the
// caller's JSON takes beyond that.
void check_glb_length(const std::string& path, std::uint64_t bin_bytes, std::uint64_t json_bytes) {
  if (bin_bytes + json_bytes > std::numeric_limits<std::uint32_t>::max() - (std::uint64_t{1} << 20)) {
    throw io_error(path,
                   "the arrays take " + std::to_string(bin_bytes) +
                       " bytes, more than a GLB file holds (4 GiB); use --export obj-sequence or pc2",
                   0);
  }
}

// final.glb's document (gltf.h): the sheet `mesh` of `model` with its arrays in buffer 0, the
// material, the mesh, its node and the scene. `extra_bin_bytes` and `extra_json_bytes` are what the
// caller adds to the file (animation.glb's targets), for the size check.
struct SheetDocument {
  gltf::Model file;
  GlbCounts counts;
  bool one_wide = false;  // a polyline or points: no normals
};

SheetDocument sheet_document(const std::string& path, const ClothModel& model, SheetMesh mesh, const GlbFrame& frame,
                             std::uint64_t extra_bin_bytes = 0, std::uint64_t extra_json_bytes = 0) {
  SheetDocument document;
  const std::size_t vertices = mesh.vertex_count();
  document.one_wide = model.rows == 1 || model.cols == 1;
  const bool one_wide = document.one_wide;
  document.counts = GlbCounts{vertices, one_wide ? 0 : mesh.triangle_vertices.size()};

  // The arrays, in float32 (uint32 indices).
  std::vector<float> vertex_position = to_float32(mesh.vertex_position);
  // A polyline has no normals.
  std::vector<float> vertex_normal = one_wide ? std::vector<float>{} : to_float32(mesh.vertex_normal);
  // Texture coordinates as final.obj's (io/obj.cpp), v flipped for glTF's top-left origin.
  std::vector<float> vertex_uv(2 * vertices);
  const double u_step = model.cols > 1 ? 1.0 / (model.cols - 1) : 0.0;
  const double v_step = model.rows > 1 ? 1.0 / (model.rows - 1) : 0.0;
  for (std::size_t v = 0; v < vertices; ++v) {
    const auto [row, col] = sheet_vertex_lattice_coordinate(model, mesh.vertex_source[v]);
    vertex_uv[2 * v] = static_cast<float>(col * u_step);
    vertex_uv[2 * v + 1] = static_cast<float>(1.0 - row * v_step);
  }
  std::vector<std::uint32_t> index;
  int mode = TINYGLTF_MODE_TRIANGLES;
  if (!one_wide) {
    index.reserve(3 * mesh.triangle_vertices.size());
    for (const auto& triangle : mesh.triangle_vertices) index.insert(index.end(), triangle.begin(), triangle.end());
  } else {
    // A chain of particles: a line along each intact connector, as the OBJ's polyline.
    mode = TINYGLTF_MODE_LINE;
    for (std::size_t e = 0; e < model.connector_count(); ++e) {
      if (model.connector_live[e] == 0) continue;
      const auto [a, b] = model.connector_particles[e];
      index.push_back(std::min(a, b));
      index.push_back(std::max(a, b));
    }
    if (index.empty()) {
      mode = TINYGLTF_MODE_POINTS;
      for (std::uint32_t p = 0; p < model.particle_count(); ++p) index.push_back(p);
    }
  }
  mesh = SheetMesh{};  // its arrays are copied: free it before the file's own copies
  const std::size_t bin_bytes = (vertex_position.size() + vertex_normal.size() + vertex_uv.size()) * sizeof(float) +
                                index.size() * sizeof(std::uint32_t);
  check_glb_length(path, bin_bytes + extra_bin_bytes, extra_json_bytes);

  gltf::Model& file = document.file;
  file.asset.version = "2.0";
  file.asset.generator = "clothsim";
  file.buffers.emplace_back();
  file.buffers.front().data.reserve(bin_bytes);

  gltf::Primitive primitive;
  primitive.mode = mode;
  primitive.attributes["POSITION"] = add_array(file, vertex_position, 3, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                               TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
  if (!one_wide) {
    primitive.attributes["NORMAL"] = add_array(file, vertex_normal, 3, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                               TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
  }
  primitive.attributes["TEXCOORD_0"] =
      add_array(file, vertex_uv, 2, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, TINYGLTF_TARGET_ARRAY_BUFFER);
  primitive.indices = add_array(file, index, 1, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                                TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  // The arrays are in the buffer now.
  vertex_position = {};
  vertex_normal = {};
  vertex_uv = {};
  index = {};

  gltf::Material material;
  material.name = "clothsim_sheet";
  material.doubleSided = true;
  material.pbrMetallicRoughness.baseColorFactor.assign(kSheetColour.begin(), kSheetColour.end());
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 0.9;
  file.materials.push_back(material);
  primitive.material = 0;

  gltf::Mesh sheet;
  sheet.name = "clothsim_sheet";
  sheet.primitives.push_back(primitive);
  file.meshes.push_back(sheet);

  gltf::Node node;
  node.name = "clothsim_sheet";
  node.mesh = 0;
  gltf::Value::Object extras;
  extras["scene"] = gltf::Value(frame.scene);
  extras["frame"] = frame.frame <= static_cast<std::size_t>(INT_MAX) ? gltf::Value(static_cast<int>(frame.frame))
                                                                     : gltf::Value(static_cast<double>(frame.frame));
  extras["time"] = gltf::Value(frame.time);
  extras["unit"] = gltf::Value(std::string("m"));
  node.extras = gltf::Value(std::move(extras));
  file.nodes.push_back(node);

  gltf::Scene scene;
  scene.name = frame.scene;
  scene.nodes.push_back(0);
  file.scenes.push_back(scene);
  file.defaultScene = 0;
  return document;
}

// Writes the bytes of `values` to `out`.
template <typename T, std::size_t N>
void write_bytes(std::ostream& out, std::span<const T, N> values) {
  out.write(reinterpret_cast<const char*>(values.data()), static_cast<std::streamsize>(values.size_bytes()));
}

// animation.glb's JSON, less than this a frame (measured: about 560 bytes with its two accessors
// with bounds, their buffer views, its target and its name), for the size check and estimate.
constexpr std::uint64_t kAnimationJsonBytesPerFrame = 700;

// Frame k's displacements from the base (frame 0) in float32: of the sheet mesh's positions
// (`position` [3 vertices]) and normals (`normal`, the same or empty for a polyline), with their
// bounds. A displacement is taken from the base as rounded to float32, so that base + target
// rounds once.
struct FrameTarget {
  std::vector<float> position, normal;
  std::array<std::vector<double>, 2> position_bounds, normal_bounds;
};

}  // namespace

std::size_t glb_bytes_for(std::size_t rows, std::size_t cols) {
  const std::size_t cells = rows > 0 && cols > 0 ? (rows - 1) * (cols - 1) : 0;
  // Per vertex: position and normal (3 floats each), texture coordinates (2); 3 indices a triangle.
  const std::size_t arrays = rows * cols * 8 * sizeof(float) + 2 * cells * 3 * sizeof(std::uint32_t);
  return SheetMesh::bytes_for(rows, cols) + 2 * arrays;
}

GlbCounts write_glb(const std::string& path, const ClothModel& model, std::span<const Vec3> position,
                    const GlbFrame& frame) {
  SheetDocument document = sheet_document(path, model, sheet_mesh_to_write(path, "write_glb", model, position), frame);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw io_error(path, "cannot create file", errno);
  errno = 0;
  gltf::TinyGLTF writer;
  const bool serialised = writer.WriteGltfSceneToStream(&document.file, out, false, true);
  out.close();
  if (!serialised || out.fail()) throw io_error(path, "write failed", errno);
  return document.counts;
}

std::size_t glb_animation_memory_for(std::size_t rows, std::size_t cols, std::size_t frames) {
  constexpr std::size_t kDocumentBytesPerFrame = 8192;
  return glb_bytes_for(rows, cols) + SheetMesh::bytes_for(rows, cols) +
         rows * cols * (sizeof(Vec3) + 6 * sizeof(float)) + frames * kDocumentBytesPerFrame;
}

std::uint64_t glb_animation_bytes_for(std::size_t rows, std::size_t cols, std::size_t frames) {
  const std::uint64_t vertices = std::uint64_t{rows} * cols;
  const std::uint64_t cells = rows > 0 && cols > 0 ? std::uint64_t{rows - 1} * (cols - 1) : 0;
  const bool one_wide = rows == 1 || cols == 1;
  const std::uint64_t f = frames;
  // The base mesh as final.glb's (position, normal, uv; 3 indices a triangle, or 2 a line), a
  // position (and normal) displacement per vertex and frame, a time per frame, F weights per frame,
  // the JSON.
  const std::uint64_t base = vertices * (one_wide ? 5 : 8) * 4 + (one_wide ? 2 * vertices : 6 * cells) * 4;
  const std::uint64_t targets = f * vertices * (one_wide ? 12 : 24);
  return base + targets + 4 * f + 4 * f * f + kAnimationJsonBytesPerFrame * f + 4096;
}

GlbCounts write_glb_animation(const std::string& path, const ClothModel& model, const GlbAnimation& animation,
                              const GlbFrameReader& read_frame) {
  const std::size_t frames = animation.frames;
  if (frames == 0) throw io_error(path, "write_glb_animation: no frames", 0);
  std::vector<Vec3> position(model.particle_count());
  read_frame(0, position);
  SheetMesh mesh = sheet_mesh_to_write(path, "write_glb_animation", model, position);
  const std::vector<float> base_position = to_float32(mesh.vertex_position);
  const std::vector<float> base_normal = to_float32(mesh.vertex_normal);
  const std::size_t vertices = mesh.vertex_count();
  const bool one_wide = model.rows == 1 || model.cols == 1;

  // Frame k's target from its particle positions: the mesh of the model's (last) topology placed
  // at them (build_sheet_mesh keeps the topology, which the model fixes), less the base.
  const auto frame_target = [&](std::size_t k, FrameTarget& target) {
    read_frame(k, position);
    build_sheet_mesh(model, position, SheetMeshMode::particles, mesh);
    const auto displacement = [](std::span<const Vec3> values, const std::vector<float>& base,
                                 std::vector<float>& out) {
      out.resize(3 * values.size());
      for (std::size_t v = 0; v < values.size(); ++v) {
        out[3 * v] = static_cast<float>(values[v].x - static_cast<double>(base[3 * v]));
        out[3 * v + 1] = static_cast<float>(values[v].y - static_cast<double>(base[3 * v + 1]));
        out[3 * v + 2] = static_cast<float>(values[v].z - static_cast<double>(base[3 * v + 2]));
      }
    };
    displacement(mesh.vertex_position, base_position, target.position);
    target.position_bounds = component_bounds(std::span<const float>(target.position), 3);
    if (!one_wide) {
      displacement(mesh.vertex_normal, base_normal, target.normal);
      target.normal_bounds = component_bounds(std::span<const float>(target.normal), 3);
    }
  };

  // The binary chunk: the base mesh's arrays and the frame times (in the document's buffer), then
  // streamed: each frame's position and normal displacements, the weights.
  const std::uint64_t target_bytes = std::uint64_t{vertices} * 3 * sizeof(float);
  const std::uint64_t frame_bytes = (one_wide ? 1 : 2) * target_bytes;
  const std::uint64_t weight_bytes = std::uint64_t{frames} * frames * sizeof(float);
  SheetDocument document =
      sheet_document(path, model, mesh, GlbFrame{animation.scene, 0, 0.0}, frames * (frame_bytes + 4) + weight_bytes,
                     kAnimationJsonBytesPerFrame * frames);
  gltf::Model& file = document.file;
  gltf::Mesh& sheet = file.meshes.front();
  gltf::Primitive& primitive = sheet.primitives.front();
  file.nodes.front().extras.Get<gltf::Value::Object>()["frames"] = gltf::Value(static_cast<int>(frames));
  file.nodes.front().extras.Get<gltf::Value::Object>()["fps"] = gltf::Value(animation.fps);

  // Frame k at t = k / fps, as the run's frames.
  std::vector<float> time(frames);
  for (std::size_t k = 0; k < frames; ++k) time[k] = static_cast<float>(static_cast<double>(k) / animation.fps);
  const int time_accessor = add_array(file, time, 1, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, 0);
  std::size_t offset = file.buffers.front().data.size();

  // The targets, from a first pass over the frames for their bounds (the JSON, which holds them,
  // comes before the binary chunk). Every target's accessors have a buffer view of their own (the
  // glTF validator wants byteStride on a view that several vertex accessors share).
  gltf::Value::Array target_names;
  FrameTarget target;
  for (std::size_t k = 0; k < frames; ++k) {
    frame_target(k, target);
    std::map<std::string, int> attributes;
    attributes["POSITION"] = add_accessor(file, add_view(file, offset, target_bytes, TINYGLTF_TARGET_ARRAY_BUFFER),
                                          vertices, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
                                          target.position_bounds[0], target.position_bounds[1]);
    offset += target_bytes;
    if (!one_wide) {
      attributes["NORMAL"] = add_accessor(file, add_view(file, offset, target_bytes, TINYGLTF_TARGET_ARRAY_BUFFER),
                                          vertices, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
                                          target.normal_bounds[0], target.normal_bounds[1]);
      offset += target_bytes;
    }
    primitive.targets.push_back(std::move(attributes));
    std::array<char, 32> name{};
    std::snprintf(name.data(), name.size(), "frame_%06zu", k);
    target_names.emplace_back(std::string(name.data()));
  }
  sheet.weights.assign(frames, 0.0);  // at rest, the base: frame 0
  gltf::Value::Object mesh_extras;
  mesh_extras["targetNames"] = gltf::Value(std::move(target_names));  // Blender's and three.js's shape key names
  sheet.extras = gltf::Value(std::move(mesh_extras));

  // The weights: at frame k's time, 1 for target k and 0 for the others, linearly interpolated
  // between frames, so that the mesh between frames k and k+1 is their linear blend.
  const int weight_accessor =
      add_accessor(file, add_view(file, offset, weight_bytes, 0), std::size_t{frames} * frames,
                   TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, {frames > 1 ? 0.0 : 1.0}, {1.0});
  offset += weight_bytes;
  gltf::Animation play;
  play.name = animation.scene;
  gltf::AnimationSampler sampler;
  sampler.input = time_accessor;
  sampler.output = weight_accessor;
  sampler.interpolation = "LINEAR";
  play.samplers.push_back(sampler);
  gltf::AnimationChannel channel;
  channel.sampler = 0;
  channel.target_node = 0;
  channel.target_path = "weights";
  play.channels.push_back(channel);
  file.animations.push_back(play);

  // The JSON: tinygltf's, of the document without its buffer, which it would write into the file
  // whole; the buffer (its length only: it is the binary chunk) goes in by hand.
  std::vector<unsigned char> head = std::move(file.buffers.front().data);
  file.buffers.clear();
  std::ostringstream json_text;
  gltf::TinyGLTF writer;
  writer.WriteGltfSceneToStream(&file, json_text, false, false);
  std::string json = json_text.str();
  if (json.empty() || json.front() != '{') throw io_error(path, "tinygltf wrote no JSON object", 0);
  json.insert(1, "\"buffers\":[{\"byteLength\":" + std::to_string(offset) + "}],");
  json.resize((json.size() + 3) / 4 * 4, ' ');  // chunks are 4-byte aligned; JSON's padding is spaces
  const std::uint64_t total = 12 + 8 + json.size() + 8 + offset;
  if (total > std::numeric_limits<std::uint32_t>::max()) {
    throw io_error(path, "the file would take " + std::to_string(total) + " bytes, more than a GLB file holds (4 GiB)",
                   0);
  }

  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw io_error(path, "cannot create file", errno);
  errno = 0;
  const std::array<std::uint32_t, 3> header = {0x46546C67u, 2u, static_cast<std::uint32_t>(total)};  // "glTF"
  write_bytes(out, std::span(header));
  const std::array<std::uint32_t, 2> json_chunk = {static_cast<std::uint32_t>(json.size()), 0x4E4F534Au};  // "JSON"
  write_bytes(out, std::span(json_chunk));
  write_bytes(out, std::span<const char>(json));
  const std::array<std::uint32_t, 2> bin_chunk = {static_cast<std::uint32_t>(offset), 0x004E4942u};  // "BIN"
  write_bytes(out, std::span(bin_chunk));
  write_bytes(out, std::span<const unsigned char>(head));
  for (std::size_t k = 0; k < frames; ++k) {
    frame_target(k, target);
    write_bytes(out, std::span<const float>(target.position));
    if (!one_wide) write_bytes(out, std::span<const float>(target.normal));
  }
  std::vector<float> weight(frames, 0.0f);
  for (std::size_t k = 0; k < frames; ++k) {
    weight[k] = 1.0f;
    write_bytes(out, std::span<const float>(weight));
    weight[k] = 0.0f;
  }
  out.close();
  if (out.fail()) throw io_error(path, "write failed", errno);
  return document.counts;
}

}  // namespace clothsim
