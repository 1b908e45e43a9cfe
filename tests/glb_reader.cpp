// tinygltf's loader for the tests (glb_reader.h): its implementation, without image support (the
// files have no images), compiled once, into the tests' clothsim_test_glb_reader library (tests/CMakeLists.txt).
#include "glb_reader.h"

#include <cstring>

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

namespace clothsim::testing {
namespace {

// The values of accessor `index` as T (the component type must be T's), tightly packed or not.
template <typename T>
bool read_accessor(const tinygltf::Model& file, int index, int component_type, int components, std::vector<T>& out,
                   std::string& error) {
  if (index < 0 || static_cast<std::size_t>(index) >= file.accessors.size()) {
    error += "no accessor " + std::to_string(index) + "; ";
    return false;
  }
  const tinygltf::Accessor& accessor = file.accessors[static_cast<std::size_t>(index)];
  if (accessor.componentType != component_type ||
      tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(accessor.type)) != components) {
    error += "accessor " + std::to_string(index) + " has another type; ";
    return false;
  }
  const tinygltf::BufferView& view = file.bufferViews[static_cast<std::size_t>(accessor.bufferView)];
  const tinygltf::Buffer& buffer = file.buffers[static_cast<std::size_t>(view.buffer)];
  const int stride = accessor.ByteStride(view);
  const std::size_t element = sizeof(T) * static_cast<std::size_t>(components);
  out.resize(accessor.count * static_cast<std::size_t>(components));
  for (std::size_t k = 0; k < accessor.count; ++k) {
    const std::size_t offset = view.byteOffset + accessor.byteOffset + k * static_cast<std::size_t>(stride);
    if (offset + element > buffer.data.size() || offset + element > view.byteOffset + view.byteLength) {
      error += "accessor " + std::to_string(index) + " runs past its buffer view; ";
      return false;
    }
    std::memcpy(out.data() + k * static_cast<std::size_t>(components), buffer.data.data() + offset, element);
  }
  return true;
}

}  // namespace

GlbMesh read_glb(const std::filesystem::path& path) {
  GlbMesh mesh;
  tinygltf::Model file;
  tinygltf::TinyGLTF loader;
  std::string warning;
  if (!loader.LoadBinaryFromFile(&file, &mesh.error, &warning, path.string())) {
    mesh.error += warning;
    return mesh;
  }
  mesh.error = warning;
  mesh.version = file.asset.version;
  mesh.scenes = file.scenes.size();
  mesh.nodes = file.nodes.size();
  mesh.meshes = file.meshes.size();
  mesh.materials = file.materials.size();
  mesh.default_scene = file.defaultScene;
  if (file.meshes.empty() || file.meshes.front().primitives.empty()) {
    mesh.error += "no mesh primitive";
    return mesh;
  }
  mesh.primitives = file.meshes.front().primitives.size();
  const tinygltf::Primitive& primitive = file.meshes.front().primitives.front();
  mesh.mode = primitive.mode;
  if (primitive.material >= 0 && static_cast<std::size_t>(primitive.material) < file.materials.size()) {
    mesh.double_sided = file.materials[static_cast<std::size_t>(primitive.material)].doubleSided;
  }
  const auto attribute = [&](const char* name) {
    const auto found = primitive.attributes.find(name);
    return found == primitive.attributes.end() ? -1 : found->second;
  };
  bool ok = read_accessor(file, attribute("POSITION"), TINYGLTF_COMPONENT_TYPE_FLOAT, 3, mesh.position, mesh.error) &&
            read_accessor(file, attribute("TEXCOORD_0"), TINYGLTF_COMPONENT_TYPE_FLOAT, 2, mesh.uv, mesh.error) &&
            read_accessor(file, primitive.indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, 1, mesh.index, mesh.error);
  if (ok && attribute("NORMAL") >= 0) {
    ok = read_accessor(file, attribute("NORMAL"), TINYGLTF_COMPONENT_TYPE_FLOAT, 3, mesh.normal, mesh.error);
  }
  if (ok) {
    const tinygltf::Accessor& positions = file.accessors[static_cast<std::size_t>(attribute("POSITION"))];
    mesh.position_min = positions.minValues;
    mesh.position_max = positions.maxValues;
  }
  mesh.accessors = file.accessors.size();
  for (const tinygltf::Accessor& accessor : file.accessors) {
    mesh.accessors_without_bounds += accessor.minValues.empty() || accessor.maxValues.empty();
    mesh.non_float_accessors += accessor.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT &&
                                accessor.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  }
  mesh.mesh_weights = file.meshes.front().weights;
  for (const auto& target : primitive.targets) {
    const auto read_target = [&](const char* name, std::vector<std::vector<float>>& out) {
      const auto found = target.find(name);
      if (found == target.end()) return;
      out.emplace_back();
      ok = ok && read_accessor(file, found->second, TINYGLTF_COMPONENT_TYPE_FLOAT, 3, out.back(), mesh.error);
    };
    read_target("POSITION", mesh.target_position);
    read_target("NORMAL", mesh.target_normal);
  }
  mesh.animations = file.animations.size();
  if (!file.animations.empty()) {
    const tinygltf::Animation& animation = file.animations.front();
    mesh.channels = animation.channels.size();
    if (!animation.channels.empty() && animation.channels.front().sampler >= 0 &&
        static_cast<std::size_t>(animation.channels.front().sampler) < animation.samplers.size()) {
      const tinygltf::AnimationChannel& channel = animation.channels.front();
      const tinygltf::AnimationSampler& sampler = animation.samplers[static_cast<std::size_t>(channel.sampler)];
      mesh.channel_node = channel.target_node;
      mesh.channel_path = channel.target_path;
      mesh.interpolation = sampler.interpolation;
      ok = ok &&
           read_accessor(file, sampler.input, TINYGLTF_COMPONENT_TYPE_FLOAT, 1, mesh.animation_time, mesh.error) &&
           read_accessor(file, sampler.output, TINYGLTF_COMPONENT_TYPE_FLOAT, 1, mesh.animation_weight, mesh.error);
      if (ok) {
        mesh.animation_time_min = file.accessors[static_cast<std::size_t>(sampler.input)].minValues;
        mesh.animation_time_max = file.accessors[static_cast<std::size_t>(sampler.input)].maxValues;
      }
    } else {
      mesh.error += "the animation has no channel with a sampler; ";
      ok = false;
    }
  }
  if (!file.nodes.empty()) {
    const tinygltf::Value& extras = file.nodes.front().extras;
    if (extras.Has("time")) mesh.extras_time = extras.Get("time").GetNumberAsDouble();
    if (extras.Has("frame")) mesh.extras_frame = extras.Get("frame").GetNumberAsInt();
  }
  mesh.loaded = ok;
  return mesh;
}

}  // namespace clothsim::testing
