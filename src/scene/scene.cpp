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
//
// The parts: json_fields.h reads and checks single values (from JSON and from --set text) and
// parses JSON text; anchors_json.h reads, checks and writes anchors and cuts; colliders_json.h the
// obstacles; material_json.h the material object; paper_args.h the paper's argument vector;
// validate_scene.h the checks of a whole scene; scene_model.h builds the model and the initial
// state from a scene. This file keeps the reader of the whole document and of the paper's
// argument vector, the single-field setter (--set) and the writer back to JSON.
#include "scene/scene.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/input_file.h"
#include "scene/anchors_json.h"
#include "scene/colliders_json.h"
#include "scene/json_fields.h"
#include "scene/material_json.h"
#include "scene/paper_args.h"
#include "scene/parameters.h"
#include "scene/validate_scene.h"

namespace clothsim {

using namespace scene_json;

namespace {

std::string method_choices() {
  return join_names(std::array{to_string(IntegratorKind::rkf45), to_string(IntegratorKind::rk4),
                               to_string(IntegratorKind::symplectic_euler), to_string(IntegratorKind::implicit_euler),
                               to_string(IntegratorKind::imex)});
}

// backend and precision: names.
std::string backend_choices() { return join_names(std::array{to_string(Backend::cpu), to_string(Backend::vulkan)}); }

std::string precision_choices() {
  return join_names(std::array{std::string_view(to_string(PrecisionRequest::float64)),
                               std::string_view(to_string(PrecisionRequest::float32)),
                               std::string_view(to_string(PrecisionRequest::automatic))});
}

void read_backend(std::string_view text, SceneSpec& spec, const std::string& source, const std::string& got) {
  if (!parse_backend(text, spec.backend.kind))
    fail(source, "backend", "must be one of " + backend_choices() + ", got " + got);
}

void read_precision(std::string_view text, SceneSpec& spec, const std::string& source, const std::string& got) {
  PrecisionRequest precision = PrecisionRequest::float64;
  if (!parse_precision_request(text, precision)) {
    fail(source, "precision",
         "must be one of " + precision_choices() + " (or absent: the backend's default), got " + got);
  }
  spec.backend.precision = precision;
}

// ---------------------------------------------------------------------------------------------
// output.export: a list of format names, each at most once.

constexpr std::array<ExportFormat, 4> kExportFormats = {ExportFormat::pc2, ExportFormat::obj_sequence,
                                                        ExportFormat::gltf, ExportFormat::gltf_animation};

std::string export_choices() {
  std::vector<std::string_view> names;
  for (ExportFormat format : kExportFormats) names.push_back(to_string(format));
  return join_names(names);
}

// Appends the format named `name` (a repeat is dropped: asking twice means the same file), or
// fails naming the field and the formats there are.
void add_export(std::vector<ExportFormat>& exports, std::string_view name, const std::string& got,
                const std::string& source) {
  ExportFormat format{};
  if (!parse_export_format(name, format)) {
    fail(source, "output.export", "each item must be one of " + export_choices() + ", got " + got);
  }
  if (std::find(exports.begin(), exports.end(), format) == exports.end()) exports.push_back(format);
}

std::vector<ExportFormat> read_exports(const json& value, const std::string& source) {
  if (!value.is_array()) {
    fail(source, "output.export",
         "must be a list of export formats (" + export_choices() + "), got " + describe_json(value));
  }
  std::vector<ExportFormat> exports;
  for (const json& item : value) {
    add_export(exports, item.is_string() ? item.get<std::string>() : "", describe_choice(item), source);
  }
  return exports;
}

// "pc2,obj-sequence"; "" or "none" for no exports.
std::vector<ExportFormat> read_text_exports(std::string_view text, const std::string& source) {
  std::vector<ExportFormat> exports;
  if (trim(text) == "none") return exports;
  for (std::string_view item : split_list(text)) add_export(exports, item, quoted(item), source);
  return exports;
}

// ---------------------------------------------------------------------------------------------
// The JSON document.

struct SceneReader {
  const std::string& source;
  const std::string& base_folder;  // where mesh files are found
  SceneSpec spec;
  const json* anchors = nullptr;    // read last: presets and index ranges need the final lattice
  const json* colliders = nullptr;  // read once after both passes: meshes are files
  const json* material = nullptr;   // applied after the first pass: it needs the final spacing

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
  } else if (key == "backend") {
    read_backend(value.is_string() ? value.get<std::string>() : "", spec, source, describe_choice(value));
  } else if (key == "precision") {
    if (value.is_null()) {
      spec.backend.precision.reset();
    } else {
      read_precision(value.is_string() ? value.get<std::string>() : "", spec, source, describe_choice(value));
    }
  } else if (key == "output.export") {
    spec.output.exports = read_exports(value, source);
  } else if (key == "paper_args") {
    apply_paper_arguments(spec, read_paper_arguments(value, source));
  } else if (key == "anchors") {
    anchors = &value;
  } else if (key == "cuts") {
    spec.cuts = read_cuts(value, source);
  } else if (key == "colliders") {
    colliders = &value;
  } else if (key == "material") {
    material = &value;
  } else {
    read_object(value, key);  // a group: child_names() listed it, so it has known keys below
  }
}

}  // namespace

// -----------------------------------------------------------------------------------------------
// Public API.

std::string_view to_string(ExportFormat format) {
  switch (format) {
    case ExportFormat::pc2: return "pc2";
    case ExportFormat::obj_sequence: return "obj-sequence";
    case ExportFormat::gltf: return "gltf";
    case ExportFormat::gltf_animation: return "gltf-animation";
  }
  return "unknown";
}

bool parse_export_format(std::string_view text, ExportFormat& format) {
  for (ExportFormat candidate : kExportFormats) {
    if (to_string(candidate) == text) {
      format = candidate;
      return true;
    }
  }
  return false;
}

SceneSpec parse_scene(std::string_view json_text, const std::string& source, const std::string& base_folder) {
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
  SceneReader reader{source, base_folder, SceneSpec{}};
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
  if (reader.colliders != nullptr) reader.spec.colliders = read_colliders(*reader.colliders, source, base_folder);
  validate_scene(reader.spec, source);
  return reader.spec;
}

SceneSpec load_scene_file(const std::string& path) {
  return parse_scene(read_input_file(path), path, std::filesystem::path(path).parent_path().string());
}

IntegratorSettings scene_integrator(const SceneSpec& spec) {
  IntegratorSettings integrator = spec.integrator;
  if (integrator.time_step > 0.0) return integrator;
  integrator.time_step = integrator.kind == IntegratorKind::implicit_euler ? 1.0 / spec.output.fps : kDefaultTimeStep;
  return integrator;
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
    spec.name = read_text_string(value, source, field);
  } else if (key == "description") {
    spec.description = read_text_string(value, source, field);
  } else if (key == "integrator.method") {
    if (!parse_integrator_kind(trim(value), spec.integrator.kind)) {
      fail(source, field, "must be one of " + method_choices() + ", got " + quoted(value));
    }
  } else if (key == "backend") {
    read_backend(trim(value), spec, source, quoted(value));
  } else if (key == "precision") {
    read_precision(trim(value), spec, source, quoted(value));
  } else if (key == "output.export") {
    spec.output.exports = read_text_exports(value, source);
  } else if (key == "paper_args") {
    apply_paper_arguments(spec, read_text_paper_arguments(value, source));
  } else if (key == "material" && trim(value) == "none") {
    spec.material.reset();  // a record only: the lattice keeps its values
  } else if (key == "material") {
    const std::string_view text = trim(value);
    // A preset name goes into a JSON string, which must be UTF-8 (its error message quotes it).
    const json material =
        text.starts_with('{') ? parse_json(text, source) : json(read_text_string(text, source, field));
    set_scene_material(spec, read_material(material, source, field), source);
  } else if (key == "cuts") {
    spec.cuts = read_cuts(parse_json(trim(value), source), source);
  } else if (key == "colliders") {
    // Mesh files named on the command line are found from the working directory.
    spec.colliders = read_colliders(parse_json(trim(value), source), source, "");
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
      case ParameterType::integer: at(parameter.key) = static_cast<std::int64_t>(value); break;
      case ParameterType::boolean: at(parameter.key) = value != 0.0; break;
      case ParameterType::real: at(parameter.key) = value; break;
      case ParameterType::limit: at(parameter.key) = value == kInfinity ? json(nullptr) : json(value); break;
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
  out["backend"] = std::string(to_string(spec.backend.kind));
  out["precision"] = spec.backend.precision ? json(to_string(*spec.backend.precision)) : json(nullptr);
  at("output.export") = json::array();
  for (ExportFormat format : spec.output.exports) at("output.export").push_back(std::string(to_string(format)));
  out["anchors"] = json::array();
  for (const AnchorSpec& anchor : spec.anchors) out["anchors"].push_back(anchor_to_json(anchor));
  out["cuts"] = json::array();
  for (const CutSpec& cut : spec.cuts) {
    out["cuts"].push_back({{"from", {cut.from[0], cut.from[1]}}, {"to", {cut.to[0], cut.to[1]}}});
  }
  out["colliders"] = json::array();
  for (const ColliderSpec& collider : spec.colliders) out["colliders"].push_back(collider_to_json(collider));
  return out;
}

void set_scene_material(SceneSpec& spec, const MaterialDef& material, const std::string& source) {
  apply_material(material, spec.lattice.spacing, spec.lattice, source);
  spec.material = material;
}

}  // namespace clothsim
