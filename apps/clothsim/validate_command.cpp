// `clothsim validate FILE...`: parse, validate and build each scene without running it, one
// line per scene; exit 2 if any is invalid. The same checks as `clothsim run`, minus the flags and
// the output folder, so a scene that validates also starts.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "core/error.h"
#include "run/run_scene.h"
#include "scene/builtin_scenes.h"
#include "scene/scene_model.h"
#include "scene/validate_scene.h"

namespace clothsim::cli {
namespace {

struct ValidateOptions {
  std::vector<std::string> scenes;
};

int validate(const ValidateOptions& options) {
  int exit_code = kExitSuccess;
  for (const std::string& scene : options.scenes) {
    try {
      const SceneSpec spec = load_scene(scene);
      validate_scene(spec, scene);
      check_export_sizes(spec);
      const ClothModel model = build_model(spec);
      std::printf("ok  %s: %s, %s\n", scene.c_str(), describe_lattice(model).c_str(),
                  describe_run_settings(spec).c_str());
    } catch (const InputError& error) {
      std::fflush(stdout);  // keep the lines in order when stdout and stderr share a terminal
      print_error(error.what());
      exit_code = kExitBadInput;
    }
  }
  std::fflush(stdout);
  return exit_code;
}

}  // namespace

Subcommand add_validate_command(CLI::App& parent) {
  auto options = std::make_shared<ValidateOptions>();
  CLI::App* app = parent.add_subcommand("validate", "Check scene files (or built-in names) without running them");
  app->add_option("SCENE", options->scenes, "scene files or built-in scene names")->required()->type_name("");
  std::string footer =
      "Prints one line per valid scene and an error for each invalid one; exits 2 if any is invalid.\n"
      "\n"
      "Examples:\n"
      "  clothsim validate my-scene.json\n"
      "  clothsim validate scenes/*.json paper-fig4\n"
      "\n"
      "Exit codes:\n"
      "  0    every scene is valid\n"
      "  2    at least one scene is invalid (its error is on stderr)";
  app->footer(footer);
  return {app, [options] { return validate(*options); }};
}

}  // namespace clothsim::cli
