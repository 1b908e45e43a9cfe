// Anchors and cuts in scene files: reading and checking the "anchors" list (each anchor's particle,
// origin, path and release time; fixed, linear, sinusoid and keyframes paths) and the "cuts" list,
// and writing an anchor back as JSON.
//
// Internal to src/scene: scene.cpp reads the document and hands these two keys here, and the
// values are read through json_fields.h. The presets themselves (parse_anchor_preset(), scene.h)
// and the anchors resolved on the lattice (resolve_anchors(), scene_model.h) are public.
#pragma once

#include <string>
#include <vector>

#include "scene/json_fields.h"
#include "scene/scene.h"

namespace clothsim::scene_json {

// The names of the anchor presets: "center, corners, edge-corners, none".
std::string preset_choices();

// "cuts": a list of {"from": [row, col], "to": [row, col]}.
std::vector<CutSpec> read_cuts(const json& value, const std::string& source);
// "anchors": a preset name or a list of anchor objects, with rows and columns inside `lattice`.
std::vector<AnchorSpec> read_anchors(const json& value, const LatticeDef& lattice, const std::string& source);
// A path object ("fixed", "linear", "sinusoid", "keyframes"), as anchors and colliders take it;
// `field` is its place ("colliders[1].path"). The origin is not part of the object.
AnchorPath read_anchor_path(const json& value, const std::string& source, const std::string& field);
// The path object as read_anchor_path() reads it (no origin).
json anchor_path_to_json(const AnchorPath& path);
// The path's fields checked again (scenes built in code); `field` is its place.
void validate_anchor_path(const AnchorPath& path, const std::string& source, const std::string& field);
// An anchor as scene_to_json() writes it: row, col and path, origin and release_time when given.
json anchor_to_json(const AnchorSpec& anchor);

// Every field of an anchor checked again (validate_scene(): anchors built in code included), and
// its release time against the run's duration. `field` is its place, "anchors[2]".
void validate_anchor(const AnchorSpec& anchor, const LatticeDef& lattice, double duration, const std::string& source,
                     const std::string& field);

}  // namespace clothsim::scene_json
