// `clothsim scenes` and `clothsim params`: what a user can run and what they can set.
//
// `params` prints the parameter registry (scene/parameters.h), the same table the scene parser,
// --set and the docs are built from, so the list can never drift from what the parser accepts.
// One line per key, so that `clothsim params | grep damping` finds a key with its range.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "commands.h"
#include "scene/builtin_scenes.h"
#include "scene/parameters.h"

namespace clothsim::cli {
namespace {

int list_scenes() {
  const std::vector<BuiltinScene> scenes = builtin_scenes();
  std::size_t width = 0;
  for (const BuiltinScene& scene : scenes) width = std::max(width, scene.name.size());
  std::printf("Built-in scenes (run one with 'clothsim run NAME'):\n\n");
  const std::size_t indent = 2 + width + 2;
  for (const BuiltinScene& scene : scenes) {
    std::printf("  %-*s  %s\n", static_cast<int>(width), scene.name.c_str(),
                wrap_text(scene.description, 100, indent).c_str());
  }
  return kExitSuccess;
}

struct ParameterRow {
  std::string key;
  std::string unit;
  std::string allowed;
  std::string default_value;
  std::string description;
};

// "an integer in [1, 4096]" -> "integer in [1, 4096]": the table reads better without articles.
std::string without_article(std::string text) {
  for (std::string_view article : {"an ", "a "}) {
    if (text.starts_with(article)) return text.substr(article.size());
  }
  return text;
}

// The keys that are not scalars or vectors (special_keys()); described here for the listing.
ParameterRow special_row(std::string_view key, const SceneSpec& defaults) {
  ParameterRow row{std::string(key), "", "", "", ""};
  if (key == "name") {
    row = {row.key, "", "text", defaults.name, "scene name; the default output folder is out/<name>"};
  } else if (key == "description") {
    row = {row.key, "", "text", "\"\"", "free text describing the scene"};
  } else if (key == "integrator.method") {
    row = {row.key, "", "rkf45|rk4|symplectic-euler|implicit-euler|imex",
           std::string(to_string(defaults.integrator.kind)), "time integrator (--integrator)"};
  } else if (key == "anchors") {
    row = {row.key, "", "preset or JSON list", defaults.anchors.empty() ? "none" : "",
           "anchored particles: center, corners, edge-corners, none, or a JSON list (--anchor)"};
  } else if (key == "material") {
    row = {row.key, "", material_preset_names() + " or JSON object", "-",
           "sets mass, springs and limits from physical units at lattice.spacing (--material; "
           "docs/materials.md)"};
  } else if (key == "output.export") {
    row = {row.key, "", "list of pc2, obj-sequence, gltf, gltf-animation", "none",
           "files for other tools: a PC2 point cache with rest.obj, one OBJ per frame, the last frame as glTF, "
           "every frame as one animated glTF "
           "(--export; docs/exports.md)"};
  } else if (key == "paper_args") {
    row = {row.key, "", "10 numbers", "-",
           "the paper's argument vector: sets the lattice and springs, anchors the centre (--paper-args)"};
  } else {
    row = {row.key, "", "see docs/scene-format.md", "", ""};
  }
  return row;
}

std::vector<ParameterRow> parameter_rows() {
  const SceneSpec defaults;
  std::vector<ParameterRow> rows;
  for (std::string_view key : all_scene_keys()) {
    if (const ScalarParameter* parameter = find_scalar_parameter(key)) {
      const double value = parameter->get(defaults);
      std::string default_text = format_parameter_value(parameter->type, value);
      rows.push_back({std::string(key), std::string(parameter->unit),
                      without_article(describe_allowed(parameter->type, parameter->range)), default_text,
                      std::string(parameter->description)});
    } else if (const VectorParameter* vector = find_vector_parameter(key)) {
      const Vec3 value = vector->get(defaults);
      std::string default_text = format_number(value.x);
      default_text += ',';
      default_text += format_number(value.y);
      default_text += ',';
      default_text += format_number(value.z);
      std::string allowed = "x,y,z each in ";
      allowed += describe_range(vector->component_range);
      rows.push_back(
          {std::string(key), std::string(vector->unit), allowed, default_text, std::string(vector->description)});
    } else {
      rows.push_back(special_row(key, defaults));
    }
  }
  return rows;
}

int list_parameters() {
  const std::vector<ParameterRow> rows = parameter_rows();
  ParameterRow widths{"KEY", "UNIT", "ALLOWED", "DEFAULT", "DESCRIPTION"};
  std::size_t key_width = widths.key.size();
  std::size_t unit_width = widths.unit.size();
  std::size_t allowed_width = widths.allowed.size();
  std::size_t default_width = widths.default_value.size();
  for (const ParameterRow& row : rows) {
    key_width = std::max(key_width, row.key.size());
    unit_width = std::max(unit_width, row.unit.size());
    allowed_width = std::max(allowed_width, row.allowed.size());
    default_width = std::max(default_width, row.default_value.size());
  }
  std::printf(
      "Scene parameters: nest them as objects in a scene file ({\"lattice\": {\"rows\": 21}}) or set\n"
      "them with 'clothsim run SCENE --set KEY=VALUE'. Vectors are written x,y,z; rest angles in degrees.\n\n");
  const auto print_row = [&](const ParameterRow& row) {
    std::printf("%-*s  %-*s  %-*s  %-*s  %s\n", static_cast<int>(key_width), row.key.c_str(),
                static_cast<int>(unit_width), row.unit.c_str(), static_cast<int>(allowed_width), row.allowed.c_str(),
                static_cast<int>(default_width), row.default_value.c_str(), row.description.c_str());
  };
  print_row(widths);
  for (const ParameterRow& row : rows) print_row(row);
  return kExitSuccess;
}

}  // namespace

Subcommand add_scenes_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand("scenes", "List the built-in scenes");
  app->footer(
      "Examples:\n"
      "  clothsim scenes\n"
      "  clothsim run paper-fig4\n");
  return {app, [] { return list_scenes(); }};
}

Subcommand add_params_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand("params", "List every scene parameter: key, unit, range, default");
  app->footer(
      "Examples:\n"
      "  clothsim params\n"
      "  clothsim params | grep damping\n"
      "  clothsim run paper-fig5 --set springs.connector.damping=10\n");
  return {app, [] { return list_parameters(); }};
}

}  // namespace clothsim::cli
