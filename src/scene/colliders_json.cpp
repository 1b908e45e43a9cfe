// Colliders in scene files (colliders_json.h).
//
// Each collider object is checked against the keys of its type, so that a
// "radius" on a box is an error naming the keys a box takes rather than
// silently ignored. A mesh is read here, at scene reading time, so that a
// missing or malformed OBJ fails before any output is created.
#include "scene/colliders_json.h"

#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "core/input_file.h"
#include "scene/anchors_json.h"
#include "scene/parameters.h"

namespace clothsim::scene_json {
namespace {

// Indexed by ColliderShape.
constexpr std::array<std::string_view, 5> kShapeNames = {"plane", "sphere", "box", "capsule", "mesh"};

std::string_view shape_name(ColliderShape shape) { return kShapeNames[static_cast<std::size_t>(shape)]; }

// Keys of a collider object of each shape; "type", "friction" and "path" are
// common to all.
std::vector<std::string> shape_keys(ColliderShape shape) {
  std::vector<std::string> keys = {"type", "friction", "path"};
  switch (shape) {
    case ColliderShape::plane: keys.insert(keys.end(), {"point", "normal"}); break;
    case ColliderShape::sphere: keys.insert(keys.end(), {"center", "radius"}); break;
    case ColliderShape::box: keys.insert(keys.end(), {"center", "half_extents"}); break;
    case ColliderShape::capsule: keys.insert(keys.end(), {"a", "b", "radius"}); break;
    case ColliderShape::mesh: keys.insert(keys.end(), {"file", "scale", "translate"}); break;
  }
  return keys;
}

// The keys a shape needs; the others of shape_keys() are optional.
std::vector<std::string> required_keys(ColliderShape shape) {
  switch (shape) {
    case ColliderShape::plane: return {"normal"};  // point defaults to the origin
    case ColliderShape::sphere: return {"center", "radius"};
    case ColliderShape::box: return {"center", "half_extents"};
    case ColliderShape::capsule: return {"a", "b", "radius"};
    case ColliderShape::mesh: return {"file"};
  }
  return {};
}

ColliderShape read_shape(const json& object, const std::string& source, const std::string& field) {
  const auto type = object.find("type");
  if (type == object.end()) fail(source, field + ".type", "is required: one of " + join_names(kShapeNames));
  if (type->is_string()) {
    for (std::size_t k = 0; k < kShapeNames.size(); ++k) {
      if (type->get<std::string>() == kShapeNames[k]) return static_cast<ColliderShape>(k);
    }
  }
  fail(source, field + ".type", "must be one of " + join_names(kShapeNames) + ", got " + describe_choice(*type));
}

// A plane's normal: any non-zero direction, stored unit. One already unit to rounding is kept as
// written: normalising is not idempotent in floating point ([1, 1, 0] / its length has a length
// one ulp off 1, and dividing again changes its last bit), so a scene.json written back would
// otherwise read a different plane and not reproduce its run bit for bit.
Vec3 read_normal(const json& value, const std::string& source, const std::string& field) {
  const Vec3 normal = read_vector(value, kColliderPositionRange, source, field);
  const double length = norm(normal);
  if (!(length > 0.0)) fail(source, field, "must be a non-zero direction [x, y, z], got [0, 0, 0]");
  if (std::abs(length - 1.0) <= 8.0 * std::numeric_limits<double>::epsilon()) return normal;
  return normal / length;
}

double read_size(const json& value, const std::string& source, const std::string& field) {
  return read_value(value, ParameterType::real, kColliderSizeRange, source, field);
}

Vec3 read_half_extents(const json& value, const std::string& source, const std::string& field) {
  const Vec3 half = read_vector(value, kColliderPositionRange, source, field);
  for (int axis = 0; axis < 3; ++axis) {
    if (!kColliderSizeRange.contains(half[axis])) {
      fail(source, field + "[" + std::to_string(axis) + "]",
           "must be a number in " + describe_range(kColliderSizeRange) + ", got " + format_number(half[axis]));
    }
  }
  return half;
}

ColliderSpec read_collider(const json& value, const std::string& source, const std::string& base_folder,
                           const std::string& field) {
  if (!value.is_object()) {
    fail(source, field, "must be an object {\"type\": \"sphere\", ...}, got " + describe_json(value));
  }
  const ColliderShape shape = read_shape(value, source, field);
  const std::vector<std::string> allowed = shape_keys(shape);
  const std::string kind(shape_name(shape));
  for (const auto& member : value.items()) {
    if (contains_name(allowed, member.key())) continue;
    fail(source, join_key(field, member.key()),
         "is not a key of a " + kind + " collider (keys of a " + kind + ": " + join_names(allowed) + ")");
  }
  for (const std::string& key : required_keys(shape)) {
    if (!value.contains(key)) fail(source, join_key(field, key), "is required for a " + kind + " collider");
  }
  ColliderSpec spec;
  Collider& collider = spec.collider;
  collider.shape = shape;
  const auto vector_at = [&](const char* key) {
    return read_vector(value.at(key), kColliderPositionRange, source, join_key(field, key));
  };
  switch (shape) {
    case ColliderShape::plane:
      if (value.contains("point")) collider.point = vector_at("point");
      collider.normal = read_normal(value.at("normal"), source, field + ".normal");
      break;
    case ColliderShape::sphere:
      collider.center = vector_at("center");
      collider.radius = read_size(value.at("radius"), source, field + ".radius");
      break;
    case ColliderShape::box:
      collider.center = vector_at("center");
      collider.half_extents = read_half_extents(value.at("half_extents"), source, field + ".half_extents");
      break;
    case ColliderShape::capsule:
      collider.a = vector_at("a");
      collider.b = vector_at("b");
      collider.radius = read_size(value.at("radius"), source, field + ".radius");
      break;
    case ColliderShape::mesh: {
      spec.mesh_file = read_string(value.at("file"), source, field + ".file");
      if (spec.mesh_file.empty()) fail(source, field + ".file", "must name an OBJ file, got an empty string");
      if (value.contains("scale")) spec.mesh_scale = read_size(value.at("scale"), source, field + ".scale");
      if (value.contains("translate")) spec.mesh_translate = vector_at("translate");
      const std::filesystem::path file(spec.mesh_file);
      collider.mesh_file = file.is_absolute() || base_folder.empty()
                               ? file.string()
                               : (std::filesystem::path(base_folder) / file).string();
      collider.mesh = read_obj_mesh(collider.mesh_file, spec.mesh_scale, spec.mesh_translate, source, field + ".file");
      break;
    }
  }
  if (value.contains("friction")) {
    collider.friction =
        read_value(value.at("friction"), ParameterType::real, kColliderFrictionRange, source, field + ".friction");
  }
  if (value.contains("path")) collider.path = read_anchor_path(value.at("path"), source, field + ".path");
  return spec;
}

// One number of an OBJ line; `where` (file and line) starts the message.
double parse_obj_number(std::string_view text, const std::string& where, const std::string& source,
                        const std::string& field) {
  double number = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), number);
  if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(number)) {
    fail(source, field, where + ": expected a number, got " + quoted(text));
  }
  return number;
}

std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t start = 0;
  while (start < line.size()) {
    while (start < line.size() && (line[start] == ' ' || line[start] == '\t')) ++start;
    std::size_t end = start;
    while (end < line.size() && line[end] != ' ' && line[end] != '\t') ++end;
    if (end > start) words.push_back(line.substr(start, end - start));
    start = end;
  }
  return words;
}

}  // namespace

std::shared_ptr<const TriangleMesh> read_obj_mesh(const std::string& path, double scale, const Vec3& translate,
                                                  const std::string& source, const std::string& field) {
  std::string text;
  try {
    text = read_input_file(path);
  } catch (const InputError& error) {
    fail(source, field, "mesh file '" + path + "' cannot be read (" + error.what() + ")");
  }
  return parse_obj_mesh(text, path, scale, translate, source, field);
}

std::shared_ptr<const TriangleMesh> parse_obj_mesh(std::string_view text, const std::string& path, double scale,
                                                   const Vec3& translate, const std::string& source,
                                                   const std::string& field) {
  TriangleMesh mesh;
  struct Corner {
    long long index;  // as written: 1-based, or negative from the end
    std::size_t line;
  };
  std::vector<std::array<Corner, 3>> triangles;
  std::size_t line_number = 0;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    start = end + 1;
    ++line_number;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::vector<std::string_view> words = split_words(line);
    if (words.empty()) continue;
    const std::string where = "mesh file '" + path + "' line " + std::to_string(line_number);
    if (words[0] == "v") {
      if (words.size() < 4 || words.size() > 5) {
        fail(source, field, where + ": a vertex is 'v x y z' (an optional w), got " + quoted(line));
      }
      const Vec3 local{parse_obj_number(words[1], where, source, field),
                       parse_obj_number(words[2], where, source, field),
                       parse_obj_number(words[3], where, source, field)};
      const Vec3 vertex = scale * local + translate;
      // Where any other collider may be: the distance arithmetic squares products of coordinates,
      // and a far vertex (1e111) made it overflow to NaN and the distances wrong.
      for (int axis = 0; axis < 3; ++axis) {
        if (!kColliderPositionRange.contains(vertex[axis])) {
          fail(source, field,
               where + ": a vertex must lie in " + describe_range(kColliderPositionRange) +
                   " m on each axis once scaled and translated, got " + format_number(vertex[axis]));
        }
      }
      mesh.vertex.push_back(vertex);
    } else if (words[0] == "f") {
      if (words.size() < 4) fail(source, field, where + ": a face needs at least 3 vertices, got " + quoted(line));
      std::vector<Corner> polygon;
      for (std::size_t k = 1; k < words.size(); ++k) {
        // "a", "a/b", "a//c" or "a/b/c": the vertex index is the part before
        // the first slash.
        const std::string_view index_text = words[k].substr(0, words[k].find('/'));
        long long index = 0;
        const auto [last, error] = std::from_chars(index_text.data(), index_text.data() + index_text.size(), index);
        if (error != std::errc() || last != index_text.data() + index_text.size() || index == 0) {
          fail(source, field,
               where +
                   ": a face corner must be a vertex index (1-based, or "
                   "negative), got " +
                   quoted(words[k]));
        }
        // A negative index counts back from the vertices read so far.
        if (index < 0) index += static_cast<long long>(mesh.vertex.size()) + 1;
        polygon.push_back({index, line_number});
      }
      // Fanned from the first corner: exact for the convex polygons modelling
      // tools write.
      for (std::size_t k = 1; k + 1 < polygon.size(); ++k)
        triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
    }
    // Other lines (vn, vt, o, g, s, usemtl, mtllib, l, ...) carry nothing a
    // collider needs.
  }
  for (const auto& triangle : triangles) {
    std::array<std::uint32_t, 3> corners{};
    for (int k = 0; k < 3; ++k) {
      const Corner& corner = triangle[k];
      if (corner.index < 1 || corner.index > static_cast<long long>(mesh.vertex.size())) {
        fail(source, field,
             "mesh file '" + path + "' line " + std::to_string(corner.line) + ": vertex index " +
                 std::to_string(corner.index) + " is outside [1, " + std::to_string(mesh.vertex.size()) + "]");
      }
      corners[k] = static_cast<std::uint32_t>(corner.index - 1);
    }
    mesh.triangle.push_back(corners);
  }
  if (mesh.triangle.empty()) fail(source, field, "mesh file '" + path + "' holds no faces ('f' lines)");
  prepare_triangle_mesh(mesh);
  return std::make_shared<const TriangleMesh>(std::move(mesh));
}

std::vector<ColliderSpec> read_colliders(const json& value, const std::string& source, const std::string& base_folder) {
  if (!value.is_array()) {
    fail(source, "colliders", "must be a list of collider objects {\"type\": ...}, got " + describe_json(value));
  }
  std::vector<ColliderSpec> colliders;
  for (std::size_t i = 0; i < value.size(); ++i) {
    colliders.push_back(read_collider(value[i], source, base_folder, "colliders[" + std::to_string(i) + "]"));
  }
  return colliders;
}

json collider_to_json(const ColliderSpec& spec) {
  const auto vector_json = [](const Vec3& v) { return json::array({v.x, v.y, v.z}); };
  const Collider& collider = spec.collider;
  json out = {{"type", shape_name(collider.shape)}};
  switch (collider.shape) {
    case ColliderShape::plane:
      out["point"] = vector_json(collider.point);
      out["normal"] = vector_json(collider.normal);
      break;
    case ColliderShape::sphere:
      out["center"] = vector_json(collider.center);
      out["radius"] = collider.radius;
      break;
    case ColliderShape::box:
      out["center"] = vector_json(collider.center);
      out["half_extents"] = vector_json(collider.half_extents);
      break;
    case ColliderShape::capsule:
      out["a"] = vector_json(collider.a);
      out["b"] = vector_json(collider.b);
      out["radius"] = collider.radius;
      break;
    case ColliderShape::mesh:
      out["file"] = spec.mesh_file;
      out["scale"] = spec.mesh_scale;
      out["translate"] = vector_json(spec.mesh_translate);
      break;
  }
  // Absent friction means the scene's collision.friction; a fixed path means at
  // rest.
  if (collider.friction >= 0.0) out["friction"] = collider.friction;
  if (collider.path.kind != AnchorPathKind::fixed) out["path"] = anchor_path_to_json(collider.path);
  return out;
}

void validate_collider(const ColliderSpec& spec, const std::string& source, const std::string& field) {
  const Collider& collider = spec.collider;
  const auto check_vector = [&](const Vec3& v, const ValueRange& range, const std::string& name) {
    for (int axis = 0; axis < 3; ++axis) {
      if (!range.contains(v[axis])) {
        fail(source, field + name + "[" + std::to_string(axis) + "]",
             "must be a number in " + describe_range(range) + ", got " + format_number(v[axis]));
      }
    }
  };
  const auto check_size = [&](double value, const std::string& name) {
    if (!kColliderSizeRange.contains(value)) {
      fail(source, field + name,
           "must be a number in " + describe_range(kColliderSizeRange) + ", got " + format_number(value));
    }
  };
  switch (collider.shape) {
    case ColliderShape::plane:
      check_vector(collider.point, kColliderPositionRange, ".point");
      check_vector(collider.normal, kColliderPositionRange, ".normal");
      if (std::abs(norm(collider.normal) - 1.0) > 1e-9) {
        fail(source, field + ".normal", "must be a unit vector, got length " + format_number(norm(collider.normal)));
      }
      break;
    case ColliderShape::sphere:
      check_vector(collider.center, kColliderPositionRange, ".center");
      check_size(collider.radius, ".radius");
      break;
    case ColliderShape::box:
      check_vector(collider.center, kColliderPositionRange, ".center");
      check_vector(collider.half_extents, kColliderSizeRange, ".half_extents");
      break;
    case ColliderShape::capsule:
      check_vector(collider.a, kColliderPositionRange, ".a");
      check_vector(collider.b, kColliderPositionRange, ".b");
      check_size(collider.radius, ".radius");
      break;
    case ColliderShape::mesh:
      check_size(spec.mesh_scale, ".scale");
      check_vector(spec.mesh_translate, kColliderPositionRange, ".translate");
      if (collider.mesh == nullptr || collider.mesh->triangle.empty()) {
        fail(source, field + ".file", "a mesh collider needs a mesh with triangles (read from its file)");
      }
      break;
  }
  // Negative: the scene's collision.friction.
  if (!(collider.friction < 0.0) && !kColliderFrictionRange.contains(collider.friction)) {
    fail(source, field + ".friction",
         "must be a number in " + describe_range(kColliderFrictionRange) + ", got " + format_number(collider.friction));
  }
  if (collider.path.kind == AnchorPathKind::driven) {
    fail(source, field + ".path",
         "must be one of fixed, linear, sinusoid, keyframes (driven paths are "
         "the viewer's)");
  }
  validate_anchor_path(collider.path, source, field + ".path");
}

}  // namespace clothsim::scene_json
