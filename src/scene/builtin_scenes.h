// The built-in scene library ("paper-fig4", "tablecloth", ...), shared by tests, benchmarks and
// the tools (STYLE.md rule 15), so that the scene benchmarked is the scene tested.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "scene/scene.h"

namespace clothsim {

// Built-in scenes, looked up by name ("paper-fig4", ...).
struct BuiltinScene {
  std::string name;
  std::string description;
};
std::vector<BuiltinScene> builtin_scenes();
bool is_builtin_scene(std::string_view name);
SceneSpec builtin_scene(std::string_view name);
// A file path or a built-in name.
SceneSpec load_scene(const std::string& file_or_name);

}  // namespace clothsim
