// Colliders in scene files: reading and checking the "colliders" list (plane,
// sphere, box, capsule and mesh obstacles, each with an optional friction and
// path), reading the OBJ files of mesh colliders, and writing a collider back
// as JSON.
//
// Internal to src/scene, like anchors_json.h: scene.cpp hands the "colliders"
// key here, values are read through json_fields.h and paths through the
// anchors' path reader, so a collider's path takes exactly the forms and checks
// an anchor's does.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "model/collider.h"
#include "scene/json_fields.h"
#include "scene/scene.h"

namespace clothsim::scene_json {

// Ranges of collider fields: positions and translations m, radii and half
// extents m, mesh scale.
inline constexpr ValueRange kColliderPositionRange = closed_range(-1e6, 1e6);
inline constexpr ValueRange kColliderSizeRange = left_open_range(0.0, 1e6);
inline constexpr ValueRange kColliderFrictionRange = closed_range(0.0, 10.0);

// "colliders": a list of collider objects. Mesh files are found relative to
// `base_folder`.
std::vector<ColliderSpec> read_colliders(const json& value, const std::string& source, const std::string& base_folder);
// A collider as scene_to_json() writes it: its type and shape fields (a mesh's
// file, scale and translate as given), friction when set, path when it moves.
json collider_to_json(const ColliderSpec& collider);
// Every field checked again (scenes built in code); `field` is its place,
// "colliders[2]".
void validate_collider(const ColliderSpec& collider, const std::string& source, const std::string& field);

// A Wavefront OBJ triangle mesh: `v x y z` and `f a b c ...` lines (indices
// 1-based, negative ones relative to the end, `a/b/c` forms accepted, polygons
// fanned from their first corner); other lines are ignored. Coordinates are
// scaled by `scale` then translated by `translate`, must then lie in
// kColliderPositionRange, and the pseudonormals are computed. Errors are
// InputError(source, field, ...) naming `path` and, for a malformed file, the line.
std::shared_ptr<const TriangleMesh> read_obj_mesh(const std::string& path, double scale, const Vec3& translate,
                                                  const std::string& source, const std::string& field);
// The same for OBJ text already read; `path` names it in messages.
std::shared_ptr<const TriangleMesh> parse_obj_mesh(std::string_view text, const std::string& path, double scale,
                                                   const Vec3& translate, const std::string& source,
                                                   const std::string& field);

}  // namespace clothsim::scene_json
