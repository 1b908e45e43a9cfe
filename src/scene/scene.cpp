// Scene files: JSON text -> SceneSpec -> ClothModel + ClothState.
//
// Design: the parser walks the JSON tree once, turning every object member into a dotted key
// ("lattice.rows") and looking that key up in the parameter registry (scene/parameters.h); only
// strings, the integrator enum, anchors and the paper's argument vector have hand-written
// readers. Groups ("lattice", "springs.opposite") are not listed anywhere: a key is a group when
// some registry key starts with it. So adding a parameter to the registry is enough for it to be
// parsed, set from the command line, validated, written back and documented.
//
// Every failure is an InputError naming the source, the dotted field and what is allowed, and
// unknown keys are errors at every level, with the nearest known key suggested (Levenshtein
// distance), because a silently ignored typo ("damping" spelled "dampnig") would run the wrong
// physics without a word. Per-field checks happen while reading, so that messages quote the value
// as written; cross-field checks (min_step <= max_step, anchors inside the lattice and not
// anchored twice) live in validate_scene(), which also rechecks every field so that scenes built
// in code get the same protection.
//
// Files may contain // and /* */ comments (nlohmann's ignore_comments): scene files are written
// by hand, and a comment explaining a parameter choice is worth keeping.
#include "scene/scene.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/assert.h"
#include "core/error.h"
#include "core/input_file.h"
#include "model/lattice_cuts.h"
#include "model/model_edits.h"
#include "model/spring_limits.h"
#include "scene/parameters.h"

namespace clothsim {
namespace {

using json = nlohmann::json;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

[[noreturn]] void fail(const std::string& source, const std::string& field, const std::string& reason) {
  throw InputError(source, field, reason);
}

std::string join_key(std::string_view prefix, std::string_view name) {
  return prefix.empty() ? std::string(name) : std::string(prefix) + "." + std::string(name);
}

std::string_view last_component(std::string_view key) {
  const std::size_t dot = key.rfind('.');
  return dot == std::string_view::npos ? key : key.substr(dot + 1);
}

std::string shorten(std::string text) {
  constexpr std::size_t kMaxQuoted = 60;
  if (text.size() > kMaxQuoted) text = text.substr(0, kMaxQuoted - 3) + "...";
  return text;
}

std::string quoted(std::string_view text) { return "\"" + shorten(std::string(text)) + "\""; }

// "a, b, c".
template <typename Names>
std::string join_names(const Names& names) {
  std::string text;
  for (const auto& name : names) text += (text.empty() ? "" : ", ") + std::string(name);
  return text;
}

bool contains_name(const std::vector<std::string>& names, std::string_view name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// How a JSON value is quoted after "got": `0`, `2.5`, `string "sixty"`, `boolean true`.
std::string describe_json(const json& value) {
  switch (value.type()) {
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
      return value.dump();
    case json::value_t::number_float:
      return format_number(value.get<double>());
    case json::value_t::string:
      return "string " + shorten(value.dump());
    case json::value_t::boolean:
      return std::string("boolean ") + (value.get<bool>() ? "true" : "false");
    case json::value_t::null:
      return "null";
    case json::value_t::array:
      return "array " + shorten(value.dump());
    case json::value_t::object:
      return "object " + shorten(value.dump());
    default:
      return shorten(value.dump());
  }
}

// For values that must be one of a few names: a string is quoted as is ("euler"), anything else
// with its type.
std::string describe_choice(const json& value) {
  return value.is_string() ? shorten(value.dump()) : describe_json(value);
}

// ---------------------------------------------------------------------------------------------
// Unknown keys and suggestions.

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> previous(b.size() + 1);
  std::vector<std::size_t> current(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) previous[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    current[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitution = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitution});
    }
    std::swap(previous, current);
  }
  return previous[b.size()];
}

// The candidate nearest to `name`, if it is close enough to be a plausible typo: at most 2 edits,
// or a third of the name for long names.
std::optional<std::string> nearest(std::string_view name, const std::vector<std::string>& candidates) {
  std::optional<std::string> best;
  std::size_t best_distance = std::max<std::size_t>(2, name.size() / 3) + 1;
  for (const std::string& candidate : candidates) {
    const std::size_t distance = edit_distance(name, candidate);
    if (distance < best_distance) {
      best_distance = distance;
      best = candidate;
    }
  }
  return best;
}

// "unknown field (did you mean 'lattice.cols'?)". `allowed` are the leaf names valid at this level
// and `prefix` their parent key. A name that exists elsewhere in the scene ("fps" at the top
// level) gets the full key of that place as its suggestion.
std::string unknown_field_reason(std::string_view name, std::string_view prefix,
                                 const std::vector<std::string>& allowed) {
  if (const std::optional<std::string> match = nearest(name, allowed)) {
    return "unknown field (did you mean '" + join_key(prefix, *match) + "'?)";
  }
  for (std::string_view key : all_scene_keys()) {
    if (last_component(key) == name) return "unknown field (did you mean '" + std::string(key) + "'?)";
  }
  const std::string list = join_names(allowed);
  return prefix.empty() ? "unknown field (known fields: " + list + ")"
                        : "unknown field (known fields in '" + std::string(prefix) + "': " + list + ")";
}

// Leaf names one level below `prefix` among all scene keys; "" is the top level.
std::vector<std::string> child_names(std::string_view prefix) {
  std::vector<std::string> names;
  for (std::string_view key : all_scene_keys()) {
    if (!prefix.empty()) {
      if (key.size() <= prefix.size() + 1 || !key.starts_with(prefix) || key[prefix.size()] != '.') continue;
      key.remove_prefix(prefix.size() + 1);
    }
    const std::string name(key.substr(0, key.find('.')));
    if (!contains_name(names, name)) names.push_back(name);
  }
  return names;
}

// A group of fields ("lattice", "springs.adjacent"): some known key lies below it.
bool is_group(std::string_view key) {
  return std::any_of(all_scene_keys().begin(), all_scene_keys().end(), [&](std::string_view known) {
    return known.size() > key.size() && known.starts_with(key) && known[key.size()] == '.';
  });
}

// Throws for the first member of `object` not in `allowed`.
void check_keys(const json& object, const std::vector<std::string>& allowed, const std::string& prefix,
                const std::string& source) {
  for (const auto& member : object.items()) {
    if (!contains_name(allowed, member.key())) {
      fail(source, join_key(prefix, member.key()), unknown_field_reason(member.key(), prefix, allowed));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Values from JSON.

// The value of a JSON number. Integers beyond 2^53 are returned as infinity so that range checks
// reject them instead of accepting a rounded neighbour.
double json_number(const json& value) {
  if (value.is_number_unsigned()) {
    const auto number = value.get<std::uint64_t>();
    return number > static_cast<std::uint64_t>(kLargestExactInteger) ? kInfinity : static_cast<double>(number);
  }
  if (value.is_number_integer()) {
    const auto number = value.get<std::int64_t>();
    const auto limit = static_cast<std::int64_t>(kLargestExactInteger);
    if (number > limit || number < -limit) return number > 0 ? kInfinity : -kInfinity;
    return static_cast<double>(number);
  }
  return value.get<double>();
}

double read_value(const json& value, ParameterType type, const ValueRange& range, const std::string& source,
                  const std::string& field) {
  if (type == ParameterType::boolean) {
    if (!value.is_boolean()) fail(source, field, "must be a boolean (true or false), got " + describe_json(value));
    return value.get<bool>() ? 1.0 : 0.0;
  }
  // A limit's "never" is JSON null; a number must be finite (an integer beyond 2^53 is not).
  if (type == ParameterType::limit && value.is_null()) return kInfinity;
  if (!value.is_number()) fail(source, field, "must be a number, got " + describe_json(value));
  const double number = json_number(value);
  const bool allowed = type == ParameterType::limit ? range.contains(number) : is_allowed(type, range, number);
  if (!allowed) fail(source, field, "must be " + describe_allowed(type, range) + ", got " + describe_json(value));
  return number;
}

Vec3 read_vector(const json& value, const ValueRange& range, const std::string& source, const std::string& field) {
  if (!value.is_array() || value.size() != 3) {
    fail(source, field, "must be an array of 3 numbers [x, y, z], got " + describe_json(value));
  }
  std::array<double, 3> components{};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    components[axis] = read_value(value[axis], ParameterType::real, range, source,
                                  field + "[" + std::to_string(axis) + "]");
  }
  return {components[0], components[1], components[2]};
}

std::string read_string(const json& value, const std::string& source, const std::string& field) {
  if (!value.is_string()) fail(source, field, "must be a string, got " + describe_json(value));
  return value.get<std::string>();
}

std::string method_choices() {
  return join_names(std::array{to_string(IntegratorKind::rkf45), to_string(IntegratorKind::rk4),
                               to_string(IntegratorKind::symplectic_euler), to_string(IntegratorKind::implicit_euler)});
}

// ---------------------------------------------------------------------------------------------
// Values from command-line text.

std::string_view trim(std::string_view text) {
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front()))) text.remove_prefix(1);
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.remove_suffix(1);
  return text;
}

// A number written in `text`, or nullopt. "nan" and "inf" parse (to non-finite values, which every
// range rejects); an overflowing "1e400" becomes infinity for the same reason.
std::optional<double> parse_number_text(std::string_view text) {
  text = trim(text);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty()) return std::nullopt;
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (end != text.data() + text.size()) return std::nullopt;
  if (error == std::errc::result_out_of_range) return text.front() == '-' ? -kInfinity : kInfinity;
  if (error != std::errc()) return std::nullopt;
  return value;
}

double read_text_value(std::string_view text, ParameterType type, const ValueRange& range, const std::string& source,
                       const std::string& field) {
  if (type == ParameterType::boolean) {
    const std::string_view word = trim(text);
    if (word == "true") return 1.0;
    if (word == "false") return 0.0;
    fail(source, field, "must be a boolean (true or false), got " + quoted(text));
  }
  // A limit's "never" is the word none; "inf" and overflowing numbers stay errors, as everywhere.
  if (type == ParameterType::limit && trim(text) == "none") return kInfinity;
  const std::optional<double> number = parse_number_text(text);
  if (!number) fail(source, field, "must be a number, got " + quoted(text));
  if (type == ParameterType::limit ? !range.contains(*number) : !is_allowed(type, range, *number)) {
    fail(source, field, "must be " + describe_allowed(type, range) + ", got " + quoted(trim(text)));
  }
  return *number;
}

// Splits "a,b, c" or "a b c" (brackets around the list allowed) into its items.
std::vector<std::string_view> split_list(std::string_view text) {
  text = trim(text);
  if (text.size() >= 2 && text.front() == '[' && text.back() == ']') text = text.substr(1, text.size() - 2);
  std::vector<std::string_view> items;
  std::size_t start = 0;
  const auto is_separator = [](char c) { return c == ',' || std::isspace(static_cast<unsigned char>(c)); };
  while (start < text.size()) {
    while (start < text.size() && is_separator(text[start])) ++start;
    std::size_t end = start;
    while (end < text.size() && !is_separator(text[end])) ++end;
    if (end > start) items.push_back(text.substr(start, end - start));
    start = end;
  }
  return items;
}

Vec3 read_text_vector(std::string_view text, const ValueRange& range, const std::string& source,
                      const std::string& field) {
  const std::vector<std::string_view> items = split_list(text);
  if (items.size() != 3) fail(source, field, "must be 3 numbers x,y,z, got " + quoted(text));
  std::array<double, 3> components{};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    components[axis] = read_text_value(items[axis], ParameterType::real, range, source,
                                       field + "[" + std::to_string(axis) + "]");
  }
  return {components[0], components[1], components[2]};
}

// ---------------------------------------------------------------------------------------------
// Anchors.

constexpr std::array<std::string_view, 4> kAnchorPresets = {"center", "corners", "edge-corners", "none"};

std::string preset_choices() { return join_names(kAnchorPresets); }

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
    case AnchorPathKind::fixed:
      return {"type"};
    case AnchorPathKind::linear:
      return {"type", "velocity"};
    case AnchorPathKind::sinusoid:
      return {"type", "amplitude", "frequency", "phase"};
    case AnchorPathKind::keyframes:
      return {"type", "keys"};
    case AnchorPathKind::driven:
      break;  // not a scene-file path (path_kind_name)
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
    fail(source, join_key(field, member.key()), "belongs to a " + owner + " path, not a " + kind + " one (keys of a " +
                                                    kind + " path: " + join_names(allowed) + ")");
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

std::vector<CutSpec> read_cuts(const json& value, const std::string& source) {
  if (!value.is_array()) {
    fail(source, "cuts", "must be a list of cuts {\"from\": [row, col], \"to\": [row, col]}, got " + describe_json(value));
  }
  std::vector<CutSpec> cuts;
  for (std::size_t i = 0; i < value.size(); ++i) {
    const std::string field = "cuts[" + std::to_string(i) + "]";
    const json& item = value[i];
    if (!item.is_object()) fail(source, field, "must be an object {\"from\": [row, col], \"to\": [row, col]}, got " + describe_json(item));
    check_keys(item, {"from", "to"}, field, source);
    CutSpec cut;
    for (const char* end : {"from", "to"}) {
      const std::string end_field = field + "." + end;
      if (!item.contains(end)) fail(source, end_field, "is required: a rest-lattice point [row, col] in particle spacings");
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

json anchor_to_json(const AnchorSpec& anchor) {
  const auto vector_json = [](const Vec3& v) { return json::array({v.x, v.y, v.z}); };
  json path = {{"type", path_kind_name(anchor.path.kind)}};
  switch (anchor.path.kind) {
    case AnchorPathKind::fixed:
      break;
    case AnchorPathKind::linear:
      path["velocity"] = vector_json(anchor.path.velocity);
      break;
    case AnchorPathKind::sinusoid:
      path["amplitude"] = vector_json(anchor.path.amplitude);
      path["frequency"] = anchor.path.frequency;
      path["phase"] = anchor.path.phase;
      break;
    case AnchorPathKind::keyframes:
      path["keys"] = json::array();
      for (const AnchorKey& key : anchor.path.keys) {
        path["keys"].push_back(json::array({key.time, key.offset.x, key.offset.y, key.offset.z}));
      }
      break;
    case AnchorPathKind::driven:
      break;  // unreachable: path_kind_name() rejects it above
  }
  json out = {{"row", anchor.row}, {"col", anchor.col}, {"path", path}};
  // Written only when given: its absence means "the particle's rest position", which follows the
  // lattice if rows, cols or spacing change later.
  if (anchor.origin_given) out["origin"] = vector_json(anchor.path.origin);
  // Written only when the anchor lets go: absent means never.
  if (anchor.release_time != kInfinity) out["release_time"] = anchor.release_time;
  return out;
}

void validate_anchor(const AnchorSpec& anchor, const LatticeDef& lattice, double duration, const std::string& source,
                     const std::string& field) {
  const auto check = [&](double value, ParameterType type, const ValueRange& range, const std::string& name) {
    if (!is_allowed(type, range, value)) {
      fail(source, field + name, "must be " + describe_allowed(type, range) + ", got " + format_number(value));
    }
  };
  const auto check_vector = [&](const Vec3& v, const std::string& name) {
    for (int axis = 0; axis < 3; ++axis) {
      check(v[axis], ParameterType::real, kAnchorComponentRange, name + "[" + std::to_string(axis) + "]");
    }
  };
  check(anchor.row, ParameterType::integer, closed_range(0.0, lattice.rows - 1.0), ".row");
  check(anchor.col, ParameterType::integer, closed_range(0.0, lattice.cols - 1.0), ".col");
  if (anchor.origin_given) check_vector(anchor.path.origin, ".origin");
  check_vector(anchor.path.velocity, ".path.velocity");
  check_vector(anchor.path.amplitude, ".path.amplitude");
  check(anchor.path.frequency, ParameterType::real, kAnchorFrequencyRange, ".path.frequency");
  check(anchor.path.phase, ParameterType::real, kAnchorPhaseRange, ".path.phase");
  if (anchor.path.kind == AnchorPathKind::keyframes) {
    for (std::size_t k = 0; k < anchor.path.keys.size(); ++k) {
      const std::string key = ".path.keys[" + std::to_string(k) + "]";
      check(anchor.path.keys[k].time, ParameterType::real, kAnchorKeyTimeRange, key + "[0]");
      const Vec3& offset = anchor.path.keys[k].offset;
      for (int axis = 0; axis < 3; ++axis) {
        check(offset[axis], ParameterType::real, kAnchorComponentRange, key + "[" + std::to_string(axis + 1) + "]");
      }
    }
    check_key_order(anchor.path.keys, source, field + ".path.keys");
  }
  // Within the run: a release at or after the end would never happen, which is surely not meant.
  if (anchor.release_time != kInfinity && !(anchor.release_time >= 0.0 && anchor.release_time < duration)) {
    fail(source, field + ".release_time",
         "must be within the run, in [0, output.duration) = [0, " + format_number(duration) + "), got " +
             format_number(anchor.release_time));
  }
}

// ---------------------------------------------------------------------------------------------
// Materials.

std::string material_choices() { return material_preset_names(); }

// The cross-field rule of a material object (the per-field ranges are checked while reading).
void check_material(const MaterialDef& material, const std::string& source, const std::string& field) {
  if (!(material.areal_density > 0.0)) {
    fail(source, field + ".areal_density", "is required: a material object needs its mass per area (kg/m^2)");
  }
  if (yields_after_breaking(material.yield_strain, material.break_strain)) {
    fail(source, field + ".yield_strain",
         "must be <= " + field + ".break_strain (" + format_number(material.break_strain) + "), got " +
             format_number(material.yield_strain) + ": the sheet would tear before it stretches for good");
  }
}

// A preset name, or an object of material fields (scene/parameters.h); fields not given keep
// MaterialDef's defaults (0, and never for the limits).
MaterialDef read_material(const json& value, const std::string& source, const std::string& field) {
  const std::string allowed = "must be one of " + material_choices() + " or an object of material fields, got ";
  if (value.is_string()) {
    const MaterialDef* preset = find_material_preset(value.get<std::string>());
    if (preset == nullptr) fail(source, field, allowed + describe_choice(value));
    return *preset;
  }
  if (!value.is_object()) fail(source, field, allowed + describe_json(value));
  std::vector<std::string> keys = {"name"};
  for (const MaterialParameter& parameter : material_parameters()) keys.emplace_back(parameter.key);
  check_keys(value, keys, field, source);
  MaterialDef material;
  material.name = "custom";
  for (const auto& member : value.items()) {
    const std::string member_field = join_key(field, member.key());
    if (member.key() == "name") {
      material.name = read_string(member.value(), source, member_field);
      continue;
    }
    const MaterialParameter& parameter = *find_material_parameter(member.key());
    parameter.set(material, read_value(member.value(), parameter.type, parameter.range, source, member_field));
  }
  check_material(material, source, field);
  return material;
}

// A preset as its name; anything else as the full object, limits never written as null.
json material_to_json(const MaterialDef& material) {
  const MaterialDef* preset = find_material_preset(material.name);
  if (preset != nullptr && *preset == material) return material.name;
  json out = {{"name", material.name}};
  for (const MaterialParameter& parameter : material_parameters()) {
    const double value = parameter.get(material);
    out[std::string(parameter.key)] = value == kInfinity ? json(nullptr) : json(value);
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// The paper's argument vector.

struct PaperArgument {
  std::string_view key;   // registry key the argument sets
  std::string_view name;  // as the paper lists it
};

constexpr std::array<PaperArgument, 10> kPaperArguments = {{
    {"lattice.rows", "rows"},
    {"lattice.cols", "cols"},
    {"lattice.particle_mass", "mass"},
    {"springs.adjacent.stiffness", "k adjacent"},
    {"springs.adjacent.damping", "c adjacent"},
    {"springs.opposite.stiffness", "k opposite"},
    {"springs.opposite.damping", "c opposite"},
    {"springs.connector.stiffness", "k connector"},
    {"springs.connector.damping", "c connector"},
    {"lattice.spacing", "connector length"},
}};

std::string paper_argument_field(std::size_t i) {
  return "paper_args[" + std::to_string(i) + "] (" + std::string(kPaperArguments[i].name) + ")";
}

std::string paper_argument_count_reason(std::size_t count) {
  std::vector<std::string_view> names;
  for (const PaperArgument& argument : kPaperArguments) names.push_back(argument.name);
  return "must be exactly 10 numbers (" + join_names(names) + "), got " + std::to_string(count);
}

// Sets the ten fields (values already checked) and anchors the centre particle, as in every run
// of the paper.
void apply_paper_arguments(SceneSpec& spec, const std::array<double, 10>& values) {
  for (std::size_t i = 0; i < kPaperArguments.size(); ++i) {
    find_scalar_parameter(kPaperArguments[i].key)->set(spec, values[i]);
  }
  parse_anchor_preset("center", spec.lattice, spec.anchors);
}

std::array<double, 10> read_paper_arguments(const json& value, const std::string& source) {
  if (!value.is_array()) fail(source, "paper_args", "must be an array of 10 numbers, got " + describe_json(value));
  if (value.size() != kPaperArguments.size()) fail(source, "paper_args", paper_argument_count_reason(value.size()));
  std::array<double, 10> values{};
  for (std::size_t i = 0; i < values.size(); ++i) {
    const ScalarParameter& parameter = *find_scalar_parameter(kPaperArguments[i].key);
    values[i] = read_value(value[i], parameter.type, parameter.range, source, paper_argument_field(i));
  }
  return values;
}

std::array<double, 10> read_text_paper_arguments(std::string_view text, const std::string& source) {
  const std::vector<std::string_view> items = split_list(text);
  if (items.size() != kPaperArguments.size()) fail(source, "paper_args", paper_argument_count_reason(items.size()));
  std::array<double, 10> values{};
  for (std::size_t i = 0; i < values.size(); ++i) {
    const ScalarParameter& parameter = *find_scalar_parameter(kPaperArguments[i].key);
    values[i] = read_text_value(items[i], parameter.type, parameter.range, source, paper_argument_field(i));
  }
  return values;
}

// ---------------------------------------------------------------------------------------------
// The JSON document.

// nlohmann keeps the last of two equal keys. "rows" written twice is almost surely an editing
// slip, so this parser callback reports it, with the dotted path of the object.
class DuplicateKeyCheck {
 public:
  explicit DuplicateKeyCheck(const std::string& source) : source_(source) {}

  bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start: {
        std::string path = start_element();
        containers_.push_back({std::move(path), event == json::parse_event_t::array_start, 0, {}, {}});
        break;
      }
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        containers_.pop_back();
        break;
      case json::parse_event_t::key: {
        Container& object = containers_.back();
        object.last_key = parsed.get<std::string>();
        if (!object.keys.insert(object.last_key).second) {
          fail(source_, join_key(object.path, object.last_key), "appears twice in the same object");
        }
        break;
      }
      case json::parse_event_t::value:
        start_element();
        break;
    }
    return true;
  }

 private:
  struct Container {
    std::string path;
    bool is_array = false;
    std::size_t next_index = 0;
    std::set<std::string> keys;
    std::string last_key;
  };

  // Dotted path of the value that starts now, inside the innermost container.
  std::string start_element() {
    if (containers_.empty()) return "";
    Container& parent = containers_.back();
    if (!parent.is_array) return join_key(parent.path, parent.last_key);
    return parent.path + "[" + std::to_string(parent.next_index++) + "]";
  }

  std::string source_;
  std::vector<Container> containers_;
};

// "line 3, column 7" of the character at 1-based offset `byte` (nlohmann's parse_error::byte, the
// position of the last character read).
std::string line_and_column(std::string_view text, std::size_t byte) {
  const std::size_t offset = std::min(byte > 0 ? byte - 1 : 0, text.size());  // 0-based
  const std::string_view before = text.substr(0, offset);
  const auto line = 1 + static_cast<std::size_t>(std::count(before.begin(), before.end(), '\n'));
  const std::size_t line_start = before.rfind('\n');  // npos on the first line
  const std::size_t column = line_start == std::string_view::npos ? offset + 1 : offset - line_start;
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// nlohmann's message without its "[json.exception.parse_error.101] parse error at line 3, column 7: "
// prefix, which we replace with our own position.
std::string syntax_error_detail(const std::string& what) {
  const std::size_t error_at = what.find("parse error");
  const std::size_t colon = error_at == std::string::npos ? std::string::npos : what.find(": ", error_at);
  if (colon != std::string::npos) {
    std::string detail = what.substr(colon + 2);
    // "syntax error while parsing value - ..." follows our own "JSON syntax error: ".
    constexpr std::string_view kRepeated = "syntax error ";
    if (detail.starts_with(kRepeated)) detail.erase(0, kRepeated.size());
    return detail;
  }
  const std::size_t bracket = what.find("] ");
  return bracket == std::string::npos ? what : what.substr(bracket + 2);
}

json parse_json(std::string_view text, const std::string& source) {
  try {
    return json::parse(text.begin(), text.end(), DuplicateKeyCheck(source), /*allow_exceptions=*/true,
                       /*ignore_comments=*/true);
  } catch (const json::parse_error& error) {
    fail(source, "", line_and_column(text, error.byte) + ": JSON syntax error: " + syntax_error_detail(error.what()));
  } catch (const json::exception& error) {
    fail(source, "", "JSON error: " + syntax_error_detail(error.what()));
  }
}

struct SceneReader {
  const std::string& source;
  SceneSpec spec;
  const json* anchors = nullptr;  // read last: presets and index ranges need the final lattice
  const json* material = nullptr;  // applied after the first pass: it needs the final spacing

  void read_object(const json& object, const std::string& prefix);
  void read_member(const std::string& key, const json& value);
};

void SceneReader::read_object(const json& object, const std::string& prefix) {
  if (!object.is_object()) fail(source, prefix, "must be an object, got " + describe_json(object));
  const std::vector<std::string> allowed = child_names(prefix);
  for (const auto& member : object.items()) {
    if (member.key().find('.') != std::string::npos) {
      fail(source, join_key(prefix, member.key()),
           "dotted keys are for --set; in a file, nest objects: {\"lattice\": {\"rows\": 21}}");
    }
    if (!contains_name(allowed, member.key())) {
      fail(source, join_key(prefix, member.key()), unknown_field_reason(member.key(), prefix, allowed));
    }
    read_member(join_key(prefix, member.key()), member.value());
  }
}

void SceneReader::read_member(const std::string& key, const json& value) {
  if (const ScalarParameter* parameter = find_scalar_parameter(key)) {
    parameter->set(spec, read_value(value, parameter->type, parameter->range, source, key));
  } else if (const VectorParameter* vector = find_vector_parameter(key)) {
    vector->set(spec, read_vector(value, vector->component_range, source, key));
  } else if (key == "name") {
    spec.name = read_string(value, source, key);
  } else if (key == "description") {
    spec.description = read_string(value, source, key);
  } else if (key == "integrator.method") {
    if (!value.is_string() || !parse_integrator_kind(value.get<std::string>(), spec.integrator.kind)) {
      fail(source, key, "must be one of " + method_choices() + ", got " + describe_choice(value));
    }
  } else if (key == "paper_args") {
    apply_paper_arguments(spec, read_paper_arguments(value, source));
  } else if (key == "anchors") {
    anchors = &value;
  } else if (key == "cuts") {
    spec.cuts = read_cuts(value, source);
  } else if (key == "material") {
    material = &value;
  } else {
    read_object(value, key);  // a group: child_names() listed it, so it has known keys below
  }
}

}  // namespace

// -----------------------------------------------------------------------------------------------
// Public API.

SceneSpec parse_scene(std::string_view json_text, const std::string& source) {
  const json document = parse_json(json_text, source);
  if (!document.is_object()) {
    fail(source, "", "the top level must be a JSON object {...}, got " + describe_json(document));
  }
  if (document.contains("paper_args") && (document.contains("lattice") || document.contains("springs"))) {
    fail(source, "paper_args",
         "cannot be combined with 'lattice' or 'springs': the paper's arguments already define the lattice and "
         "springs");
  }
  if (document.contains("paper_args") && document.contains("material")) {
    fail(source, "paper_args",
         "cannot be combined with 'material': the paper's arguments are raw spring constants, the material "
         "sets them from physical units");
  }
  SceneReader reader{source, SceneSpec{}};
  reader.read_object(document, "");
  json others;  // outlives the reader's pointer to its anchors
  if (reader.material != nullptr && !reader.material->is_null()) {
    // The material sets the mass, springs, rest angles and limits at the spacing the file gives;
    // keys given beside it override it, so the file is read again on top of it.
    set_scene_material(reader.spec, read_material(*reader.material, source, "material"), source);
    others = document;
    others.erase("material");
    reader.read_object(others, "");
  }
  // Without an "anchors" key, anchors stay as paper_args left them (the centre) or empty.
  if (reader.anchors != nullptr) reader.spec.anchors = read_anchors(*reader.anchors, reader.spec.lattice, source);
  validate_scene(reader.spec, source);
  return reader.spec;
}

SceneSpec load_scene_file(const std::string& path) {
  return parse_scene(read_input_file(path), path);
}

SceneSpec scene_from_paper_args(std::string_view text, const std::string& source) {
  const std::array<double, 10> values = read_text_paper_arguments(text, source);
  SceneSpec spec;
  apply_paper_arguments(spec, values);
  std::vector<std::string> numbers;
  for (double value : values) numbers.push_back(format_number(value));
  spec.name = "paper-args";
  spec.description = "The paper's argument vector [" + join_names(numbers) + "], centre particle anchored.";
  validate_scene(spec, source);
  return spec;
}

bool parse_anchor_preset(std::string_view text, const LatticeDef& lattice, std::vector<AnchorSpec>& anchors) {
  const int last_row = lattice.rows - 1;
  const int last_col = lattice.cols - 1;
  std::vector<std::array<int, 2>> cells;
  if (text == "center") {
    cells = {{lattice.rows / 2, lattice.cols / 2}};
  } else if (text == "corners") {
    cells = {{0, 0}, {0, last_col}, {last_row, 0}, {last_row, last_col}};
  } else if (text == "edge-corners") {
    cells = {{0, 0}, {0, last_col}};
  } else if (text != "none") {
    return false;
  }
  // A lattice one particle wide has coincident corners; anchor each particle once.
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  anchors.clear();
  for (const auto& [row, col] : cells) anchors.push_back(AnchorSpec{row, col, AnchorPath{}, false});
  return true;
}

void set_scene_field(SceneSpec& spec, std::string_view key, std::string_view value, const std::string& source) {
  const std::string field(key);
  if (const ScalarParameter* parameter = find_scalar_parameter(key)) {
    parameter->set(spec, read_text_value(value, parameter->type, parameter->range, source, field));
  } else if (const VectorParameter* vector = find_vector_parameter(key)) {
    vector->set(spec, read_text_vector(value, vector->component_range, source, field));
  } else if (key == "name") {
    spec.name = std::string(value);
  } else if (key == "description") {
    spec.description = std::string(value);
  } else if (key == "integrator.method") {
    if (!parse_integrator_kind(trim(value), spec.integrator.kind)) {
      fail(source, field, "must be one of " + method_choices() + ", got " + quoted(value));
    }
  } else if (key == "paper_args") {
    apply_paper_arguments(spec, read_text_paper_arguments(value, source));
  } else if (key == "material" && trim(value) == "none") {
    spec.material.reset();  // a record only: the lattice keeps its values
  } else if (key == "material") {
    const std::string_view text = trim(value);
    const json material = text.starts_with('{') ? parse_json(text, source) : json(std::string(text));
    set_scene_material(spec, read_material(material, source, field), source);
  } else if (key == "cuts") {
    spec.cuts = read_cuts(parse_json(trim(value), source), source);
  } else if (key == "anchors") {
    const std::string_view text = trim(value);
    if (text.starts_with('[')) {
      spec.anchors = read_anchors(parse_json(text, source), spec.lattice, source);
    } else if (!parse_anchor_preset(text, spec.lattice, spec.anchors)) {
      fail(source, field, "must be one of " + preset_choices() + " or a JSON list of anchors, got " + quoted(value));
    }
  } else if (is_group(key)) {
    std::vector<std::string> fields;
    for (const std::string& name : child_names(key)) fields.push_back(join_key(key, name));
    fail(source, field, "is a group of fields; set one of: " + join_names(fields));
  } else {
    std::vector<std::string> keys(all_scene_keys().begin(), all_scene_keys().end());
    fail(source, field, unknown_field_reason(key, "", keys));
  }
}

void validate_scene(const SceneSpec& spec, const std::string& source) {
  for (const ScalarParameter& parameter : scalar_parameters()) {
    const double value = parameter.get(spec);
    if (!is_allowed(parameter.type, parameter.range, value)) {
      fail(source, std::string(parameter.key),
           "must be " + describe_allowed(parameter.type, parameter.range) + ", got " + format_number(value));
    }
  }
  for (const VectorParameter& parameter : vector_parameters()) {
    const Vec3 value = parameter.get(spec);
    for (int axis = 0; axis < 3; ++axis) {
      if (!parameter.component_range.contains(value[axis])) {
        fail(source, std::string(parameter.key) + "[" + std::to_string(axis) + "]",
             "must be a number in " + describe_range(parameter.component_range) + ", got " +
                 format_number(value[axis]));
      }
    }
  }
  const LatticeDef& lattice = spec.lattice;
  if (static_cast<long long>(lattice.rows) * lattice.cols < 2) {
    fail(source, "lattice.rows", "lattice.rows x lattice.cols must be at least 2 particles, got " +
                                     std::to_string(lattice.rows) + " x " + std::to_string(lattice.cols));
  }
  if (yields_after_breaking(lattice.limits.yield_strain, lattice.limits.break_strain)) {
    fail(source, "springs.connector.yield_strain",
         "must be <= springs.connector.break_strain (" + format_number(lattice.limits.break_strain) + "), got " +
             format_number(lattice.limits.yield_strain) + ": a connector would break before it stretches for good");
  }
  if (spec.material) {
    for (const MaterialParameter& parameter : material_parameters()) {
      const double value = parameter.get(*spec.material);
      if (!is_allowed(parameter.type, parameter.range, value)) {
        fail(source, "material." + std::string(parameter.key),
             "must be " + describe_allowed(parameter.type, parameter.range) + ", got " + format_number(value));
      }
    }
    check_material(*spec.material, source, "material");
  }
  const IntegratorSettings& integrator = spec.integrator;
  if (integrator.min_step > integrator.max_step) {
    fail(source, "integrator.min_step", "must be <= integrator.max_step (" + format_number(integrator.max_step) +
                                            "), got " + format_number(integrator.min_step));
  }
  if (integrator.min_step > integrator.time_step) {
    fail(source, "integrator.min_step", "must be <= integrator.time_step (" + format_number(integrator.time_step) +
                                            "), got " + format_number(integrator.min_step));
  }
  // Anchors: inside the lattice, each particle at most once. A map over the anchors, not an array
  // over the particles: a 4096 x 4096 lattice would need 64 MiB to check two anchors.
  std::map<std::uint32_t, std::size_t> anchor_of_particle;
  for (std::size_t i = 0; i < spec.anchors.size(); ++i) {
    const AnchorSpec& anchor = spec.anchors[i];
    const std::string field = "anchors[" + std::to_string(i) + "]";
    validate_anchor(anchor, lattice, spec.output.duration, source, field);
    const std::uint32_t particle = lattice_index(lattice.cols, anchor.row, anchor.col);
    const auto [previous, inserted] = anchor_of_particle.emplace(particle, i);
    if (!inserted) {
      fail(source, field, "particle (row " + std::to_string(anchor.row) + ", col " + std::to_string(anchor.col) +
                              ") is anchored twice (also by anchors[" + std::to_string(previous->second) + "])");
    }
  }
}

json scene_to_json(const SceneSpec& spec) {
  json out = json::object();
  // The node at a dotted key, created on the way down.
  const auto at = [&out](std::string_view key) -> json& {
    json* node = &out;
    std::size_t start = 0;
    while (true) {
      const std::size_t dot = key.find('.', start);
      node = &(*node)[std::string(key.substr(start, dot - start))];
      if (dot == std::string_view::npos) return *node;
      start = dot + 1;
    }
  };
  out["name"] = spec.name;
  out["description"] = spec.description;
  for (const ScalarParameter& parameter : scalar_parameters()) {
    const double value = parameter.get(spec);
    switch (parameter.type) {
      case ParameterType::integer:
        at(parameter.key) = static_cast<std::int64_t>(value);
        break;
      case ParameterType::boolean:
        at(parameter.key) = value != 0.0;
        break;
      case ParameterType::real:
        at(parameter.key) = value;
        break;
      case ParameterType::limit:
        at(parameter.key) = value == kInfinity ? json(nullptr) : json(value);
        break;
    }
  }
  // Written with the keys it set: on reading, those keys override it with the same values.
  // null: no material, the lattice's own constants.
  out["material"] = spec.material ? material_to_json(*spec.material) : json(nullptr);
  for (const VectorParameter& parameter : vector_parameters()) {
    const Vec3 value = parameter.get(spec);
    at(parameter.key) = json::array({value.x, value.y, value.z});
  }
  at("integrator.method") = std::string(to_string(spec.integrator.kind));
  out["anchors"] = json::array();
  for (const AnchorSpec& anchor : spec.anchors) out["anchors"].push_back(anchor_to_json(anchor));
  out["cuts"] = json::array();
  for (const CutSpec& cut : spec.cuts) {
    out["cuts"].push_back({{"from", {cut.from[0], cut.from[1]}}, {"to", {cut.to[0], cut.to[1]}}});
  }
  return out;
}

Vec3 lattice_rest_position(const LatticeDef& lattice, int row, int col) {
  // The same expression as build_lattice(), so that an anchor at its default origin sits exactly
  // on its particle's rest position.
  return {(col - (lattice.cols - 1) / 2.0) * lattice.spacing, 0.0, (row - (lattice.rows - 1) / 2.0) * lattice.spacing};
}

std::vector<Anchor> resolve_anchors(const SceneSpec& spec) {
  std::vector<Anchor> anchors;
  anchors.reserve(spec.anchors.size());
  for (const AnchorSpec& anchor : spec.anchors) {
    AnchorPath path = anchor.path;
    if (!anchor.origin_given) path.origin = lattice_rest_position(spec.lattice, anchor.row, anchor.col);
    anchors.push_back(Anchor{lattice_index(spec.lattice.cols, anchor.row, anchor.col), path, anchor.release_time});
  }
  return anchors;
}

void set_scene_material(SceneSpec& spec, const MaterialDef& material, const std::string& source) {
  apply_material(material, spec.lattice.spacing, spec.lattice, source);
  spec.material = material;
}

ClothModel build_model(const SceneSpec& spec) {
  const std::vector<Anchor> anchors = resolve_anchors(spec);
  ClothModel model = build_lattice(spec.lattice, spec.environment, anchors, "scene '" + spec.name + "'");
  // The scene's seed varies the break strains, as it varies the initial perturbation.
  SpringLimits limits = spec.lattice.limits;
  limits.variation_seed = spec.initial.seed;
  apply_spring_limits(model, limits);
  // Notches: broken before the run starts (t = 0), so they store no energy and book no work.
  for (const CutSpec& cut : spec.cuts) {
    for (std::uint32_t connector : connectors_crossed_in_lattice(model, cut.from, cut.to)) {
      break_connector(model, connector, 0.0);
    }
  }
  return model;
}

ClothState build_initial_state(const ClothModel& model, const SceneSpec& spec) {
  ClothState state = make_rest_state(model);
  apply_initial_conditions(model, spec.initial, state);
  return state;
}

}  // namespace clothsim
