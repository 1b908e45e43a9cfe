#include "viewer/script.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/input_file.h"
#include "scene/parameters.h"
#include "scene/validate_scene.h"

namespace clothsim::viewer {
namespace {

using json = nlohmann::json;

// Events must happen within a day of frame-clock time, a bound that keeps frame numbers exact.
constexpr double kLatestEvent = 86400.0;       // s
constexpr double kLongestDrag = 86400.0;       // s
constexpr double kFarthestTarget = 1e6;        // m, the scene's anchor coordinate bound
constexpr double kLatestFrame = 1e9;           // frames
constexpr double kFarthestLatticePoint = 1e6;  // spacings, a cut's ends
constexpr double kLargestSphere = 1e6;         // m, a sphere's radius

[[noreturn]] void fail(const std::string& source, const std::string& field, const std::string& reason) {
  throw InputError(source, field, reason);
}

std::string describe_json(const json& value) {
  std::string text = value.dump();
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  switch (value.type()) {
    case json::value_t::string: return "string " + text;
    case json::value_t::boolean: return "boolean " + text;
    case json::value_t::array: return "array " + text;
    case json::value_t::object: return "object " + text;
    default: return text;
  }
}

constexpr std::array<std::string_view, 13> kActionNames = {
    "drag",       "release", "pin", "unpin",          "pause",      "play",       "set",
    "screenshot", "quit",    "cut", "self_collision", "add_sphere", "move_sphere"};

std::string action_list() {
  std::string text;
  for (std::string_view name : kActionNames) text += (text.empty() ? "" : ", ") + std::string(name);
  return text;
}

double read_number(const json& value, double min, double max, bool min_inclusive, const std::string& source,
                   const std::string& field) {
  const ValueRange range{min, max, min_inclusive, true};
  if (!value.is_number() || !range.contains(value.get<double>())) {
    fail(source, field, "must be a number in " + describe_range(range) + ", got " + describe_json(value));
  }
  return value.get<double>();
}

// A whole number in [0, 1e6]; `what` says what it counts in messages.
int read_index(const json& value, const std::string& source, const std::string& field,
               const char* what = "a lattice index from 0") {
  if (!value.is_number_integer() && !value.is_number_unsigned()) {
    fail(source, field, std::string("must be a whole number (") + what + "), got " + describe_json(value));
  }
  const auto index = value.get<long long>();
  if (index < 0 || index > 1'000'000) fail(source, field, "must be in [0, 1000000], got " + describe_json(value));
  return static_cast<int>(index);
}

void check_keys(const json& object, std::initializer_list<std::string_view> allowed, const std::string& source,
                const std::string& field) {
  for (const auto& member : object.items()) {
    if (std::find(allowed.begin(), allowed.end(), member.key()) != allowed.end()) continue;
    std::string names;
    for (std::string_view name : allowed) names += (names.empty() ? "" : ", ") + std::string(name);
    fail(source, field.empty() ? member.key() : field + "." + member.key(),
         "unknown field (allowed here: " + names + ")");
  }
}

// {"row": R, "col": C, ...}: both required.
void read_particle(const json& value, ScriptEvent& event, const std::string& source, const std::string& field) {
  for (const char* name : {"row", "col"}) {
    if (!value.contains(name)) fail(source, field + "." + name, "is required (the particle's lattice row and column)");
  }
  event.row = read_index(value.at("row"), source, field + ".row");
  event.col = read_index(value.at("col"), source, field + ".col");
}

// [x, y, z] within the scene's coordinate bound, m.
Vec3 read_point(const json& value, const std::string& source, const std::string& field) {
  if (!value.is_array() || value.size() != 3) {
    fail(source, field, "must be an array of 3 numbers [x, y, z], got " + describe_json(value));
  }
  std::array<double, 3> components{};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    components[axis] = read_number(value[axis], -kFarthestTarget, kFarthestTarget, true, source,
                                   field + "[" + std::to_string(axis) + "]");
  }
  return {components[0], components[1], components[2]};
}

// An action's object: `fields` are its fields, all required; `shape` shows it in messages.
void check_object(const json& body, std::initializer_list<std::string_view> fields, const char* shape,
                  const std::string& source, const std::string& field) {
  if (!body.is_object()) {
    fail(source, field, std::string("must be an object ") + shape + ", got " + describe_json(body));
  }
  check_keys(body, fields, source, field);
  for (std::string_view name : fields) {
    if (!body.contains(name)) fail(source, field + "." + std::string(name), "is required");
  }
}

// The value of a "set" entry as --set text: numbers in full precision, vectors "x,y,z".
std::string assignment_text(const json& value, const std::string& source, const std::string& field) {
  const auto number_text = [](double number) { return format_number(number); };
  if (value.is_number()) return number_text(value.get<double>());
  if (value.is_string()) return value.get<std::string>();
  if (value.is_boolean()) return value.get<bool>() ? "true" : "false";
  if (value.is_array() && value.size() == 3 &&
      std::all_of(value.begin(), value.end(), [](const json& v) { return v.is_number(); })) {
    return number_text(value[0].get<double>()) + "," + number_text(value[1].get<double>()) + "," +
           number_text(value[2].get<double>());
  }
  fail(source, field, "must be a number, a string or an array of 3 numbers, got " + describe_json(value));
}

ScriptEvent read_event(const json& value, std::size_t index, const std::string& source) {
  const std::string field = "events[" + std::to_string(index) + "]";
  if (!value.is_object())
    fail(source, field, "must be an object {\"at\": SECONDS, ACTION: ...}, got " + describe_json(value));
  ScriptEvent event;
  event.index = index;

  const bool has_at = value.contains("at");
  const bool has_frame = value.contains("frame");
  if (has_at == has_frame) {
    fail(source, field,
         has_at ? "give either \"at\" (seconds) or \"frame\", not both"
                : "needs a time: \"at\" (seconds on the frame clock) or \"frame\" (a frame number)");
  }
  if (has_at) {
    event.at = read_number(value.at("at"), 0.0, kLatestEvent, true, source, field + ".at");
  } else {
    const json& frame = value.at("frame");
    if (!frame.is_number_unsigned() && !(frame.is_number_integer() && frame.get<long long>() >= 0)) {
      fail(source, field + ".frame", "must be a whole number >= 0, got " + describe_json(frame));
    }
    if (frame.get<double>() > kLatestFrame) fail(source, field + ".frame", "must be at most 1e9, got " + frame.dump());
    event.by_frame = true;
    event.frame = frame.get<std::uint64_t>();
  }

  int actions = 0;
  for (const auto& member : value.items()) {
    const std::string& key = member.key();
    if (key == "at" || key == "frame") continue;
    const auto found = std::find(kActionNames.begin(), kActionNames.end(), key);
    if (found == kActionNames.end()) {
      fail(source, field + "." + key,
           "unknown field (an event has \"at\" or \"frame\" and one action: " + action_list() + ")");
    }
    ++actions;
    event.action = static_cast<ScriptAction>(found - kActionNames.begin());
  }
  if (actions != 1) {
    fail(source, field,
         (actions == 0 ? "needs an action: one of " : "has more than one action; give one of ") + action_list());
  }

  const std::string name(to_string(event.action));
  const std::string action_field = field + "." + name;
  const json& body = value.at(name);
  switch (event.action) {
    case ScriptAction::drag:
      if (!body.is_object()) {
        fail(source, action_field,
             "must be an object {\"row\": R, \"col\": C, \"to\": [x, y, z], \"duration\": SECONDS}, got " +
                 describe_json(body));
      }
      check_keys(body, {"row", "col", "to", "duration"}, source, action_field);
      read_particle(body, event, source, action_field);
      for (const char* required : {"to", "duration"}) {
        if (!body.contains(required)) fail(source, action_field + "." + required, "is required");
      }
      event.to = read_point(body.at("to"), source, action_field + ".to");
      event.duration = read_number(body.at("duration"), 0.0, kLongestDrag, false, source, action_field + ".duration");
      break;
    case ScriptAction::self_collision:
      if (!body.is_boolean()) fail(source, action_field, "must be true or false, got " + describe_json(body));
      event.on = body.get<bool>();
      break;
    case ScriptAction::add_sphere:
      check_object(body, {"center", "radius"}, "{\"center\": [x, y, z], \"radius\": R}", source, action_field);
      event.center = read_point(body.at("center"), source, action_field + ".center");
      event.radius = read_number(body.at("radius"), 0.0, kLargestSphere, false, source, action_field + ".radius");
      break;
    case ScriptAction::move_sphere:
      check_object(body, {"sphere", "to", "duration"}, "{\"sphere\": N, \"to\": [x, y, z], \"duration\": SECONDS}",
                   source, action_field);
      event.sphere = static_cast<std::size_t>(
          read_index(body.at("sphere"), source, action_field + ".sphere", "a sphere's number from 0"));
      event.to = read_point(body.at("to"), source, action_field + ".to");
      event.duration = read_number(body.at("duration"), 0.0, kLongestDrag, false, source, action_field + ".duration");
      break;
    case ScriptAction::release:
    case ScriptAction::pin:
    case ScriptAction::unpin:
      if (!body.is_object()) {
        fail(source, action_field, "must be an object {\"row\": R, \"col\": C}, got " + describe_json(body));
      }
      check_keys(body, {"row", "col"}, source, action_field);
      read_particle(body, event, source, action_field);
      break;
    case ScriptAction::pause:
    case ScriptAction::play:
    case ScriptAction::quit:
      if (!(body.is_boolean() && body.get<bool>()))
        fail(source, action_field, "must be true, got " + describe_json(body));
      break;
    case ScriptAction::set:
      if (!body.is_object() || body.empty()) {
        fail(source, action_field,
             "must be an object of scene keys and values, e.g. {\"springs.connector.stiffness\": 200}, got " +
                 describe_json(body));
      }
      for (const auto& member : body.items()) {
        event.assignments.emplace_back(member.key(),
                                       assignment_text(member.value(), source, action_field + "." + member.key()));
      }
      break;
    case ScriptAction::cut:
      if (!body.is_object()) {
        fail(source, action_field,
             "must be an object {\"from\": [row, col], \"to\": [row, col]} (rest-lattice points), got " +
                 describe_json(body));
      }
      check_keys(body, {"from", "to"}, source, action_field);
      for (const char* end : {"from", "to"}) {
        const std::string end_field = action_field + "." + end;
        if (!body.contains(end)) fail(source, end_field, "is required (a rest-lattice point [row, col])");
        const json& point = body.at(end);
        if (!point.is_array() || point.size() != 2) {
          fail(source, end_field, "must be an array of 2 numbers [row, col], got " + describe_json(point));
        }
        std::array<double, 2>& target = std::string_view(end) == "from" ? event.cut_from : event.cut_to;
        for (std::size_t axis = 0; axis < 2; ++axis) {
          target[axis] = read_number(point[axis], -kFarthestLatticePoint, kFarthestLatticePoint, true, source,
                                     end_field + "[" + std::to_string(axis) + "]");
        }
      }
      break;
    case ScriptAction::screenshot:
      if (!body.is_string() || body.get<std::string>().empty()) {
        fail(source, action_field, "must be the path of a PNG file, got " + describe_json(body));
      }
      event.path = body.get<std::string>();
      break;
  }
  return event;
}

std::string line_and_column(std::string_view text, std::size_t byte) {
  const std::size_t offset = std::min(byte > 0 ? byte - 1 : 0, text.size());
  const std::string_view before = text.substr(0, offset);
  const auto line = 1 + static_cast<std::size_t>(std::count(before.begin(), before.end(), '\n'));
  const std::size_t line_start = before.rfind('\n');
  const std::size_t column = line_start == std::string_view::npos ? offset + 1 : offset - line_start;
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

}  // namespace

std::string_view to_string(ScriptAction action) { return kActionNames[static_cast<std::size_t>(action)]; }

std::uint64_t ScriptEvent::firing_frame(double frame_time) const {
  if (by_frame) return frame;
  // The first frame k with k * frame_time >= at, forgiving a millionth of a frame of rounding.
  return static_cast<std::uint64_t>(std::max(0.0, std::ceil(at / frame_time - 1e-6)));
}

std::string ScriptEvent::describe() const {
  return "events[" + std::to_string(index) + "] (" + std::string(to_string(action)) + ")";
}

Script parse_script(std::string_view json_text, const std::string& source) {
  json document;
  try {
    document = json::parse(json_text.begin(), json_text.end(), nullptr, /*allow_exceptions=*/true,
                           /*ignore_comments=*/true);
  } catch (const json::parse_error& error) {
    std::string what = error.what();
    const std::size_t colon = what.find(": ", what.find("parse error"));
    fail(source, "",
         line_and_column(json_text, error.byte) +
             ": JSON syntax error: " + (colon == std::string::npos ? what : what.substr(colon + 2)));
  }
  if (!document.is_object()) {
    fail(source, "", "a script is a JSON object {\"events\": [...]}, got " + describe_json(document));
  }
  check_keys(document, {"events", "description"}, source, "");
  if (!document.contains("events")) fail(source, "events", "is required (the list of timed events)");
  const json& events = document.at("events");
  if (!events.is_array()) fail(source, "events", "must be a list of events, got " + describe_json(events));
  if (document.contains("description") && !document.at("description").is_string()) {
    fail(source, "description", "must be a string, got " + describe_json(document.at("description")));
  }
  Script script;
  script.source = source;
  for (std::size_t i = 0; i < events.size(); ++i) script.events.push_back(read_event(events[i], i, source));
  return script;
}

Script load_script_file(const std::string& path) { return parse_script(read_input_file(path), path); }

void check_script(const Script& script, const SceneSpec& scene) {
  // "set" events apply on top of each other in firing order, as they will in the run.
  const double frame_time = 1.0 / scene.output.fps;
  std::vector<const ScriptEvent*> order;
  for (const ScriptEvent& event : script.events) order.push_back(&event);
  std::stable_sort(order.begin(), order.end(), [frame_time](const ScriptEvent* a, const ScriptEvent* b) {
    return a->firing_frame(frame_time) < b->firing_frame(frame_time);
  });
  SceneSpec edited = scene;
  // Spheres so far: the scene's, then those the "add_sphere" events fired so far add.
  std::size_t spheres = 0;
  for (const ColliderSpec& collider : scene.colliders) spheres += collider.collider.shape == ColliderShape::sphere;
  for (const ScriptEvent* event_pointer : order) {
    const ScriptEvent& event = *event_pointer;
    const std::string field = "events[" + std::to_string(event.index) + "]." + std::string(to_string(event.action));
    switch (event.action) {
      case ScriptAction::drag:
      case ScriptAction::release:
      case ScriptAction::pin:
      case ScriptAction::unpin:
        if (event.row >= scene.lattice.rows) {
          fail(script.source, field + ".row",
               "must be in [0, " + std::to_string(scene.lattice.rows - 1) + "] (the scene has " +
                   std::to_string(scene.lattice.rows) + " rows), got " + std::to_string(event.row));
        }
        if (event.col >= scene.lattice.cols) {
          fail(script.source, field + ".col",
               "must be in [0, " + std::to_string(scene.lattice.cols - 1) + "] (the scene has " +
                   std::to_string(scene.lattice.cols) + " columns), got " + std::to_string(event.col));
        }
        break;
      case ScriptAction::set: {
        for (const auto& [key, value] : event.assignments) {
          if (!is_live_parameter(key)) {
            fail(script.source, field + "." + key,
                 "cannot change while the simulation runs; live keys: " + live_parameter_list());
          }
          set_scene_field(edited, key, value, script.source + ": " + field);
        }
        // Cross-field rules (min_step <= max_step, ...) after the whole event, as the run does.
        validate_scene(edited, script.source + ": " + field);
        break;
      }
      case ScriptAction::add_sphere: ++spheres; break;
      case ScriptAction::move_sphere:
        if (event.sphere >= spheres) {
          fail(script.source, field + ".sphere",
               spheres == 0 ? "there is no sphere to move yet (the scene has none; add one with \"add_sphere\")"
                            : "must be in [0, " + std::to_string(spheres - 1) + "] (there are " +
                                  std::to_string(spheres) + " spheres by then), got " + std::to_string(event.sphere));
        }
        break;
      case ScriptAction::pause:
      case ScriptAction::play:
      case ScriptAction::screenshot:
      case ScriptAction::quit:
      case ScriptAction::self_collision:
      case ScriptAction::cut:  // a segment off the sheet cuts nothing
        break;
    }
  }
}

}  // namespace clothsim::viewer
