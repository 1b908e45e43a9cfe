// Anchors and cuts in scene files (anchors_json.h).
#include "scene/anchors_json.h"

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "core/assert.h"
#include "scene/parameters.h"

namespace clothsim::scene_json {

constexpr std::array<std::string_view, 4> kAnchorPresets = {"center", "corners", "edge-corners", "none"};

std::string preset_choices() { return join_names(kAnchorPresets); }

namespace {

// Indexed by AnchorPathKind. Driven paths (the viewer's runtime anchors, model/anchor.h) are
// made between steps by Simulation and have no scene-file form.
constexpr std::array<std::string_view, 4> kPathKindNames = {"fixed", "linear", "sinusoid", "keyframes"};

std::string_view path_kind_name(AnchorPathKind kind) {
  CLOTHSIM_ASSERT(kind != AnchorPathKind::driven, "a scene holds no driven anchor path");
  return kPathKindNames[static_cast<std::size_t>(kind)];
}

// Keys of a path object; the first is "type", the others belong to the path kind.
std::vector<std::string> path_keys(AnchorPathKind kind) {
  switch (kind) {
    case AnchorPathKind::fixed: return {"type"};
    case AnchorPathKind::linear: return {"type", "velocity"};
    case AnchorPathKind::sinusoid: return {"type", "amplitude", "frequency", "phase"};
    case AnchorPathKind::keyframes: return {"type", "keys"};
    case AnchorPathKind::driven: break;  // not a scene-file path (path_kind_name)
  }
  return {"type"};
}

AnchorPathKind read_path_kind(const json& path, const std::string& source, const std::string& field) {
  const auto type = path.find("type");
  if (type == path.end()) return AnchorPathKind::fixed;
  if (type->is_string()) {
    for (std::size_t k = 0; k < kPathKindNames.size(); ++k) {
      if (type->get<std::string>() == kPathKindNames[k]) return static_cast<AnchorPathKind>(k);
    }
  }
  fail(source, field + ".type", "must be one of " + join_names(kPathKindNames) + ", got " + describe_choice(*type));
}

// The order of keys; the values are checked where they are read (and again in validate_anchor).
void check_key_order(const std::vector<AnchorKey>& keys, const std::string& source, const std::string& field) {
  if (keys.empty()) fail(source, field, "must hold at least one key [t, x, y, z]");
  for (std::size_t k = 1; k < keys.size(); ++k) {
    if (!(keys[k].time > keys[k - 1].time)) {
      fail(source, field + "[" + std::to_string(k) + "]",
           "time " + format_number(keys[k].time) + " s must be after the previous key's (" +
               format_number(keys[k - 1].time) + " s): keys are in strictly increasing time");
    }
  }
}

// [[t, x, y, z], ...]: time in s, offset from the path's origin in m.
std::vector<AnchorKey> read_keys(const json& value, const std::string& source, const std::string& field) {
  if (!value.is_array()) {
    fail(source, field, "must be a list of keys [t, x, y, z] (s, m), got " + describe_json(value));
  }
  std::vector<AnchorKey> keys;
  for (std::size_t k = 0; k < value.size(); ++k) {
    const std::string key_field = field + "[" + std::to_string(k) + "]";
    const json& item = value[k];
    if (!item.is_array() || item.size() != 4) {
      fail(source, key_field, "must be an array of 4 numbers [t, x, y, z] (s, m), got " + describe_json(item));
    }
    AnchorKey key;
    key.time = read_value(item[0], ParameterType::real, kAnchorKeyTimeRange, source, key_field + "[0]");
    std::array<double, 3> offset{};
    for (std::size_t axis = 0; axis < 3; ++axis) {
      offset[axis] = read_value(item[axis + 1], ParameterType::real, kAnchorComponentRange, source,
                                key_field + "[" + std::to_string(axis + 1) + "]");
    }
    key.offset = {offset[0], offset[1], offset[2]};
    keys.push_back(key);
  }
  check_key_order(keys, source, field);
  return keys;
}

AnchorPath read_path(const json& value, const std::string& source, const std::string& field) {
  if (!value.is_object()) fail(source, field, "must be an object, got " + describe_json(value));
  AnchorPath path;
  path.kind = read_path_kind(value, source, field);
  // A key of another path type is an error rather than ignored: "amplitude" on a fixed path means
  // the author expected the anchor to move.
  check_keys(value, {"type", "velocity", "amplitude", "frequency", "phase", "keys"}, field, source);
  const std::vector<std::string> allowed = path_keys(path.kind);
  const std::string kind(path_kind_name(path.kind));
  for (const auto& member : value.items()) {
    if (contains_name(allowed, member.key())) continue;
    const std::string owner = member.key() == "velocity" ? "linear" : member.key() == "keys" ? "keyframes" : "sinusoid";
    fail(source, join_key(field, member.key()),
         "belongs to a " + owner + " path, not a " + kind + " one (keys of a " + kind +
             " path: " + join_names(allowed) + ")");
  }
  if (value.contains("velocity")) {
    path.velocity = read_vector(value.at("velocity"), kAnchorComponentRange, source, field + ".velocity");
  }
  if (value.contains("amplitude")) {
    path.amplitude = read_vector(value.at("amplitude"), kAnchorComponentRange, source, field + ".amplitude");
  }
  if (value.contains("frequency")) {
    path.frequency =
        read_value(value.at("frequency"), ParameterType::real, kAnchorFrequencyRange, source, field + ".frequency");
  }
  if (value.contains("phase")) {
    path.phase = read_value(value.at("phase"), ParameterType::real, kAnchorPhaseRange, source, field + ".phase");
  }
  if (path.kind == AnchorPathKind::keyframes) {
    if (!value.contains("keys")) {
      fail(source, field + ".keys", "is required for a keyframes path: a list of [t, x, y, z] (s, m)");
    }
    path.keys = read_keys(value.at("keys"), source, field + ".keys");
  }
  return path;
}

// Row or column index in [0, count - 1].
int read_index(const json& value, int count, const std::string& source, const std::string& field) {
  return static_cast<int>(read_value(value, ParameterType::integer, closed_range(0.0, count - 1.0), source, field));
}

AnchorSpec read_anchor(const json& value, const LatticeDef& lattice, const std::string& source,
                       const std::string& field) {
  if (!value.is_object()) {
    fail(source, field, "must be an object {\"row\": ..., \"col\": ...}, got " + describe_json(value));
  }
  check_keys(value, {"row", "col", "origin", "path", "release_time"}, field, source);
  AnchorSpec anchor;
  if (value.contains("row")) anchor.row = read_index(value.at("row"), lattice.rows, source, field + ".row");
  if (value.contains("col")) anchor.col = read_index(value.at("col"), lattice.cols, source, field + ".col");
  if (value.contains("path")) anchor.path = read_path(value.at("path"), source, field + ".path");
  if (value.contains("origin")) {
    anchor.path.origin = read_vector(value.at("origin"), kAnchorComponentRange, source, field + ".origin");
    anchor.origin_given = true;
  }
  // The upper end, output.duration, is checked by validate_scene(): the duration may come later.
  if (value.contains("release_time")) {
    anchor.release_time = read_value(value.at("release_time"), ParameterType::limit, kAnchorKeyTimeRange, source,
                                     field + ".release_time");
  }
  return anchor;
}

// Points of cuts: in a generous box around any lattice (a cut may start outside the sheet).
constexpr ValueRange kCutPointRange = closed_range(-1e6, 1e6);

}  // namespace

std::vector<CutSpec> read_cuts(const json& value, const std::string& source) {
  if (!value.is_array()) {
    fail(source, "cuts",
         "must be a list of cuts {\"from\": [row, col], \"to\": [row, col]}, got " + describe_json(value));
  }
  std::vector<CutSpec> cuts;
  for (std::size_t i = 0; i < value.size(); ++i) {
    const std::string field = "cuts[" + std::to_string(i) + "]";
    const json& item = value[i];
    if (!item.is_object())
      fail(source, field, "must be an object {\"from\": [row, col], \"to\": [row, col]}, got " + describe_json(item));
    check_keys(item, {"from", "to"}, field, source);
    CutSpec cut;
    for (const char* end : {"from", "to"}) {
      const std::string end_field = field + "." + end;
      if (!item.contains(end))
        fail(source, end_field, "is required: a rest-lattice point [row, col] in particle spacings");
      const json& point = item.at(end);
      if (!point.is_array() || point.size() != 2) {
        fail(source, end_field, "must be an array of 2 numbers [row, col], got " + describe_json(point));
      }
      std::array<double, 2>& target = std::string_view(end) == "from" ? cut.from : cut.to;
      for (std::size_t axis = 0; axis < 2; ++axis) {
        target[axis] = read_value(point[axis], ParameterType::real, kCutPointRange, source,
                                  end_field + "[" + std::to_string(axis) + "]");
      }
    }
    cuts.push_back(cut);
  }
  return cuts;
}

std::vector<AnchorSpec> read_anchors(const json& value, const LatticeDef& lattice, const std::string& source) {
  const std::string allowed = "must be one of " + preset_choices() + " or a list of anchors, got ";
  std::vector<AnchorSpec> anchors;
  if (value.is_string()) {
    if (!parse_anchor_preset(value.get<std::string>(), lattice, anchors)) {
      fail(source, "anchors", allowed + describe_choice(value));
    }
    return anchors;
  }
  if (!value.is_array()) fail(source, "anchors", allowed + describe_choice(value));
  for (std::size_t i = 0; i < value.size(); ++i) {
    anchors.push_back(read_anchor(value[i], lattice, source, "anchors[" + std::to_string(i) + "]"));
  }
  return anchors;
}

AnchorPath read_anchor_path(const json& value, const std::string& source, const std::string& field) {
  return read_path(value, source, field);
}

json anchor_path_to_json(const AnchorPath& anchor_path) {
  const auto vector_json = [](const Vec3& v) { return json::array({v.x, v.y, v.z}); };
  json path = {{"type", path_kind_name(anchor_path.kind)}};
  switch (anchor_path.kind) {
    case AnchorPathKind::fixed: break;
    case AnchorPathKind::linear: path["velocity"] = vector_json(anchor_path.velocity); break;
    case AnchorPathKind::sinusoid:
      path["amplitude"] = vector_json(anchor_path.amplitude);
      path["frequency"] = anchor_path.frequency;
      path["phase"] = anchor_path.phase;
      break;
    case AnchorPathKind::keyframes:
      path["keys"] = json::array();
      for (const AnchorKey& key : anchor_path.keys) {
        path["keys"].push_back(json::array({key.time, key.offset.x, key.offset.y, key.offset.z}));
      }
      break;
    case AnchorPathKind::driven: break;  // unreachable: path_kind_name() rejects it above
  }
  return path;
}

json anchor_to_json(const AnchorSpec& anchor) {
  const auto vector_json = [](const Vec3& v) { return json::array({v.x, v.y, v.z}); };
  json out = {{"row", anchor.row}, {"col", anchor.col}, {"path", anchor_path_to_json(anchor.path)}};
  // Written only when given: its absence means "the particle's rest position", which follows the
  // lattice if rows, cols or spacing change later.
  if (anchor.origin_given) out["origin"] = vector_json(anchor.path.origin);
  // Written only when the anchor lets go: absent means never.
  if (anchor.release_time != kInfinity) out["release_time"] = anchor.release_time;
  return out;
}

namespace {

void check_field(double value, ParameterType type, const ValueRange& range, const std::string& source,
                 const std::string& field) {
  if (!is_allowed(type, range, value)) {
    fail(source, field, "must be " + describe_allowed(type, range) + ", got " + format_number(value));
  }
}

void check_vector_field(const Vec3& v, const std::string& source, const std::string& field) {
  for (int axis = 0; axis < 3; ++axis) {
    check_field(v[axis], ParameterType::real, kAnchorComponentRange, source, field + "[" + std::to_string(axis) + "]");
  }
}

}  // namespace

void validate_anchor_path(const AnchorPath& path, const std::string& source, const std::string& field) {
  check_vector_field(path.velocity, source, field + ".velocity");
  check_vector_field(path.amplitude, source, field + ".amplitude");
  check_field(path.frequency, ParameterType::real, kAnchorFrequencyRange, source, field + ".frequency");
  check_field(path.phase, ParameterType::real, kAnchorPhaseRange, source, field + ".phase");
  if (path.kind == AnchorPathKind::keyframes) {
    for (std::size_t k = 0; k < path.keys.size(); ++k) {
      const std::string key = field + ".keys[" + std::to_string(k) + "]";
      check_field(path.keys[k].time, ParameterType::real, kAnchorKeyTimeRange, source, key + "[0]");
      const Vec3& offset = path.keys[k].offset;
      for (int axis = 0; axis < 3; ++axis) {
        check_field(offset[axis], ParameterType::real, kAnchorComponentRange, source,
                    key + "[" + std::to_string(axis + 1) + "]");
      }
    }
    check_key_order(path.keys, source, field + ".keys");
  }
}

void validate_anchor(const AnchorSpec& anchor, const LatticeDef& lattice, double duration, const std::string& source,
                     const std::string& field) {
  check_field(anchor.row, ParameterType::integer, closed_range(0.0, lattice.rows - 1.0), source, field + ".row");
  check_field(anchor.col, ParameterType::integer, closed_range(0.0, lattice.cols - 1.0), source, field + ".col");
  if (anchor.origin_given) check_vector_field(anchor.path.origin, source, field + ".origin");
  validate_anchor_path(anchor.path, source, field + ".path");
  // Within the run: a release at or after the end would never happen, which is surely not meant.
  if (anchor.release_time != kInfinity && !(anchor.release_time >= 0.0 && anchor.release_time < duration)) {
    fail(source, field + ".release_time",
         "must be within the run, in [0, output.duration) = [0, " + format_number(duration) + "), got " +
             format_number(anchor.release_time));
  }
}

}  // namespace clothsim::scene_json
