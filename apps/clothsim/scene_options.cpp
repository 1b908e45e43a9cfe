#include "scene_options.h"

#include "core/error.h"
#include "scene/builtin_scenes.h"
#include "scene/parameters.h"
#include "scene/validate_scene.h"

namespace clothsim::cli {
namespace {

std::string field_flag_help(const FieldFlag& flag, std::string_view what) {
  std::string text(what.empty() ? flag.what : what);
  text += " (";
  text += flag.key;
  if (flag.value_name == "on|off") {
    // The value is the switch itself; the registry's "a boolean (true or false)" would mislead.
  } else if (const ScalarParameter* parameter = find_scalar_parameter(flag.key)) {
    text += ": ";
    text += describe_allowed(parameter->type, parameter->range);
  } else if (const VectorParameter* vector = find_vector_parameter(flag.key)) {
    text += ": each in ";
    text += describe_range(vector->component_range);
  }
  text += ")";
  return text;
}

// The text set_scene_field() takes for a flag's value: --self-collision's on|off become true|false.
std::string field_flag_value(const FieldFlag& flag, const std::string& value) {
  if (flag.flag != "--self-collision") return value;
  if (value == "on") return "true";
  if (value == "off") return "false";
  throw InputError(std::string(flag.flag), std::string(flag.key), "must be on or off, got \"" + value + "\"");
}

void add_field_flag(CLI::App& app, SceneOptions& options, std::size_t i, std::string_view what) {
  const FieldFlag& flag = kFieldFlags[i];
  app.add_option(std::string(flag.flag), options.field_values[i], field_flag_help(flag, what))
      ->type_name(std::string(flag.value_name))
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
}

}  // namespace

void add_scene_options(CLI::App& app, SceneOptions& options, std::initializer_list<FieldFlagChoice> field_flags) {
  options.app = &app;
  options.command = app.get_name();
  app.add_option("SCENE", options.scene, "scene file (JSON) or built-in scene name (see 'clothsim scenes')")
      ->type_name("");
  app.add_option("--paper-args", options.paper_args,
                 "instead of SCENE, the paper's 10 numbers: rows,cols,mass,k_adj,c_adj,k_opp,c_opp,k_conn,"
                 "c_conn,length")
      ->type_name("N,N,...");
  app.add_option("--material", options.material,
                 "sheet material: a preset (" + material_preset_names() +
                     ") or a JSON object of material fields; applied at the scene's spacing, before --set")
      ->type_name("NAME");
  for (const FieldFlagChoice& choice : field_flags) {
    std::size_t i = 0;
    while (i < kFieldFlags.size() && kFieldFlags[i].flag != choice.flag) ++i;
    if (i == kFieldFlags.size()) throw std::logic_error("add_scene_options: unknown field flag");
    add_field_flag(app, options, i, choice.what);
  }
  app.add_option("--set", options.assignments, "set any scene parameter by its key (repeatable)")
      ->type_name("KEY=VALUE")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

void add_scene_options(CLI::App& app, SceneOptions& options) {
  add_scene_options(app, options, {});
  for (std::size_t i = 0; i < kFieldFlags.size(); ++i) add_field_flag(app, options, i, {});
}

SceneSpec make_scene(const SceneOptions& options, const std::function<bool(SceneSpec&)>& extra) {
  const bool has_scene = options.given("SCENE");
  const bool has_paper_args = options.given("--paper-args");
  if (has_scene == has_paper_args) {
    throw InputError(options.command, "",
                     has_scene ? "give either SCENE or --paper-args, not both"
                               : "needs a SCENE (a scene file or a built-in name, see 'clothsim scenes') or "
                                 "--paper-args ROWS,COLS,MASS,K_ADJ,C_ADJ,K_OPP,C_OPP,K_CONN,C_CONN,LENGTH");
  }
  std::string source = has_scene ? options.scene : "--paper-args";
  SceneSpec spec = has_scene ? load_scene(options.scene) : scene_from_paper_args(options.paper_args, source);

  bool overridden = false;
  if (options.given("--material")) {
    set_scene_field(spec, "material", options.material, "--material");
    overridden = true;
  }
  for (const std::string& assignment : options.assignments) {
    const std::size_t equals = assignment.find('=');
    if (equals == std::string::npos || equals == 0) {
      std::string reason = "expects KEY=VALUE (list the keys with 'clothsim params'), got \"";
      reason += assignment;
      reason += "\"";
      throw InputError("--set", "", reason);
    }
    const std::string_view text = assignment;
    set_scene_field(spec, text.substr(0, equals), text.substr(equals + 1), "--set");
    overridden = true;
  }
  for (std::size_t i = 0; i < kFieldFlags.size(); ++i) {
    const FieldFlag& flag = kFieldFlags[i];
    // A flag the subcommand did not register has no option: app->count() would throw.
    if (options.app->get_option_no_throw(std::string(flag.flag)) == nullptr || !options.given(flag.flag)) continue;
    set_scene_field(spec, flag.key, field_flag_value(flag, options.field_values[i]), std::string(flag.flag));
    overridden = true;
  }
  if (extra && extra(spec)) overridden = true;
  if (overridden) source += " with the command-line flags";
  validate_scene(spec, source);
  return spec;
}

}  // namespace clothsim::cli
