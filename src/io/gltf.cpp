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

// Appends `values` to the buffer as a buffer view (`target`: ARRAY_BUFFER or ELEMENT_ARRAY_BUFFER)
// and an accessor of `count` elements of `type` over it; returns the accessor's index.
template <typename T>
int add_array(gltf::Model& file, const std::vector<T>& values, std::size_t count, int component_type, int type,
              int target) {
  gltf::Buffer& buffer = file.buffers.front();
  gltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.data.size();
  view.byteLength = values.size() * sizeof(T);  // a multiple of 4: every T here is 4 bytes
  view.target = target;
  const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
  buffer.data.insert(buffer.data.end(), bytes, bytes + view.byteLength);
  file.bufferViews.push_back(view);

  gltf::Accessor accessor;
  accessor.bufferView = static_cast<int>(file.bufferViews.size() - 1);
  accessor.byteOffset = 0;
  accessor.componentType = component_type;
  accessor.count = count;
  accessor.type = type;
  file.accessors.push_back(accessor);
  return static_cast<int>(file.accessors.size() - 1);
}

}  // namespace

std::size_t glb_bytes_for(std::size_t rows, std::size_t cols) {
  const std::size_t cells = rows > 0 && cols > 0 ? (rows - 1) * (cols - 1) : 0;
  // Per vertex: position and normal (3 floats each), texture coordinates (2); 3 indices a triangle.
  const std::size_t arrays = rows * cols * 8 * sizeof(float) + 2 * cells * 3 * sizeof(std::uint32_t);
  return SheetMesh::bytes_for(rows, cols) + 2 * arrays;
}

GlbCounts write_glb(const std::string& path, const ClothModel& model, std::span<const Vec3> position,
                    const GlbFrame& frame) {
  SheetMesh mesh = sheet_mesh_to_write(path, "write_glb", model, position);
  const std::size_t vertices = mesh.vertex_count();
  const bool one_wide = model.rows == 1 || model.cols == 1;
  const GlbCounts counts{vertices, one_wide ? 0 : mesh.triangle_vertices.size()};

  // The arrays, in float32 (uint32 indices).
  std::vector<float> vertex_position(3 * vertices);
  std::array<float, 3> low{}, high{};
  low.fill(std::numeric_limits<float>::infinity());
  high.fill(-std::numeric_limits<float>::infinity());
  for (std::size_t v = 0; v < vertices; ++v) {
    const Vec3& p = mesh.vertex_position[v];
    const std::array<float, 3> rounded = {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
    for (std::size_t axis = 0; axis < 3; ++axis) {
      vertex_position[3 * v + axis] = rounded[axis];
      low[axis] = std::min(low[axis], rounded[axis]);
      high[axis] = std::max(high[axis], rounded[axis]);
    }
  }
  std::vector<float> vertex_normal(one_wide ? 0 : 3 * vertices);  // a polyline has none
  for (std::size_t v = 0; v < vertex_normal.size() / 3; ++v) {
    const Vec3& normal = mesh.vertex_normal[v];
    vertex_normal[3 * v] = static_cast<float>(normal.x);
    vertex_normal[3 * v + 1] = static_cast<float>(normal.y);
    vertex_normal[3 * v + 2] = static_cast<float>(normal.z);
  }
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
  // The JSON chunk is a few kB; leave it a MiB below GLB's 32-bit total length.
  if (bin_bytes > std::numeric_limits<std::uint32_t>::max() - (std::size_t{1} << 20)) {
    throw io_error(path,
                   "the mesh's arrays take " + std::to_string(bin_bytes) +
                       " bytes, more than a GLB file holds (4 GiB); use --export obj-sequence or pc2",
                   0);
  }

  gltf::Model file;
  file.asset.version = "2.0";
  file.asset.generator = "clothsim";
  file.buffers.emplace_back();
  file.buffers.front().data.reserve(bin_bytes);

  gltf::Primitive primitive;
  primitive.mode = mode;
  primitive.attributes["POSITION"] = add_array(file, vertex_position, vertices, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                               TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
  file.accessors.back().minValues.assign(low.begin(), low.end());
  file.accessors.back().maxValues.assign(high.begin(), high.end());
  if (!one_wide) {
    primitive.attributes["NORMAL"] = add_array(file, vertex_normal, vertices, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                               TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
  }
  primitive.attributes["TEXCOORD_0"] = add_array(file, vertex_uv, vertices, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                                 TINYGLTF_TYPE_VEC2, TINYGLTF_TARGET_ARRAY_BUFFER);
  primitive.indices = add_array(file, index, index.size(), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
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

  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw io_error(path, "cannot create file", errno);
  errno = 0;
  gltf::TinyGLTF writer;
  const bool serialised = writer.WriteGltfSceneToStream(&file, out, false, true);
  out.close();
  if (!serialised || out.fail()) throw io_error(path, "write failed", errno);
  return counts;
}

}  // namespace clothsim
