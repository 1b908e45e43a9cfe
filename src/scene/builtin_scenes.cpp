// The built-in scene library, shared by tests, benchmarks and the tools (STYLE.md rule 15), so
// that the scene benchmarked is the scene tested.
//
// The paper's figures are built from its own 10-number argument vectors through
// scene_from_paper_args(), the same path a user's `paper_args` takes. The "paper material" of the
// other scenes is LatticeDef's defaults, which are the constants of those figures.
#include <algorithm>
#include <array>
#include <string>

#include "core/error.h"
#include "model/material.h"
#include "scene/scene.h"

namespace clothsim {
namespace {

SceneSpec paper_scene(std::string_view name, std::string_view arguments, std::string_view description) {
  SceneSpec spec = scene_from_paper_args(arguments, "built-in scene '" + std::string(name) + "'");
  spec.name = std::string(name);
  spec.description = std::string(description);
  return spec;
}

SceneSpec paper_fig4() {
  return paper_scene("paper-fig4", "21,21,1,4,1,1400,200,80,5,1",
                     "The paper's Figure 4: a 21 x 21 sheet held by its centre particle at the origin; at rest it "
                     "folds in on itself. Paper arguments [21, 21, 1, 4, 1, 1400, 200, 80, 5, 1].");
}

SceneSpec paper_fig5() {
  return paper_scene("paper-fig5", "11,11,1,4,1,1400,200,80,5,1",
                     "The paper's Figure 5: an 11 x 11 sheet held by its centre particle at the origin. Paper "
                     "arguments [11, 11, 1, 4, 1, 1400, 200, 80, 5, 1].");
}

SceneSpec paper_fig6() {
  return paper_scene("paper-fig6", "11,11,1,400,10,1400,200,80,5,1",
                     "The paper's Figure 6: as Figure 5 with stiffer adjacent radial springs (k 400, c 10), so "
                     "the sheet keeps more of its shape. Paper arguments [11, 11, 1, 400, 10, 1400, 200, 80, 5, 1].");
}

SceneSpec drape_corners() {
  SceneSpec spec;
  spec.name = "drape-corners";
  spec.description =
      "A 25 x 25 sheet of the paper's material hung by the two corners of row 0, draping under gravity.";
  spec.lattice.rows = 25;
  spec.lattice.cols = 25;
  parse_anchor_preset("edge-corners", spec.lattice, spec.anchors);
  return spec;
}

SceneSpec free_spin() {
  SceneSpec spec;
  spec.name = "free-spin";
  spec.description =
      "An 11 x 11 sheet of the paper's material spinning freely without gravity or anchors, slightly "
      "perturbed: total linear and angular momentum must stay constant.";
  spec.lattice.rows = 11;
  spec.lattice.cols = 11;
  spec.environment.gravity = {0.0, 0.0, 0.0};
  spec.initial.angular_velocity = {0.3, 1.0, 0.2};
  spec.initial.position_noise = 0.02;
  spec.initial.velocity_noise = 0.05;
  spec.initial.seed = 7;
  spec.output.duration = 5.0;
  return spec;
}

SceneSpec cotton_drape() {
  SceneSpec spec;
  spec.name = "cotton-drape";
  spec.description =
      "A 1 m x 1 m sheet of cotton shirting (130 g/m^2, KES-F stretch, shear and bending stiffness; "
      "docs/materials.md) on a 128 x 128 lattice, hung by the two corners of row 0 and draping under gravity. "
      "Stiff: explicit methods need steps near 1e-5 s; implicit Euler takes the frame time 1/60 s.";
  spec.lattice.rows = 128;
  spec.lattice.cols = 128;
  apply_material(cotton_material(), 1.0 / 127.0, spec.lattice, "built-in scene 'cotton-drape'");
  parse_anchor_preset("edge-corners", spec.lattice, spec.anchors);
  spec.integrator.kind = IntegratorKind::implicit_euler;
  spec.integrator.time_step = 1.0 / 60.0;
  spec.output.duration = 5.0;
  return spec;
}

struct BuiltinEntry {
  std::string_view name;
  SceneSpec (*make)();
};

constexpr std::array<BuiltinEntry, 6> kBuiltins = {{
    {"paper-fig4", paper_fig4},
    {"paper-fig5", paper_fig5},
    {"paper-fig6", paper_fig6},
    {"drape-corners", drape_corners},
    {"free-spin", free_spin},
    {"cotton-drape", cotton_drape},
}};

const BuiltinEntry* find_builtin(std::string_view name) {
  const auto entry = std::find_if(kBuiltins.begin(), kBuiltins.end(),
                                  [&](const BuiltinEntry& candidate) { return candidate.name == name; });
  return entry == kBuiltins.end() ? nullptr : &*entry;
}

std::string builtin_names() {
  std::string text;
  for (const BuiltinEntry& entry : kBuiltins) text += (text.empty() ? "" : ", ") + std::string(entry.name);
  return text;
}

// A name that cannot be a file path of a scene: no directory separator, no extension.
bool looks_like_scene_name(std::string_view text) {
  return text.find('/') == std::string_view::npos && text.find('.') == std::string_view::npos;
}

}  // namespace

std::vector<BuiltinScene> builtin_scenes() {
  std::vector<BuiltinScene> scenes;
  for (const BuiltinEntry& entry : kBuiltins) {
    const SceneSpec spec = entry.make();
    scenes.push_back({spec.name, spec.description});
  }
  return scenes;
}

bool is_builtin_scene(std::string_view name) { return find_builtin(name) != nullptr; }

SceneSpec builtin_scene(std::string_view name) {
  const BuiltinEntry* entry = find_builtin(name);
  if (entry == nullptr) {
    throw InputError(std::string(name), "", "not a built-in scene (built-ins: " + builtin_names() + ")");
  }
  return entry->make();
}

SceneSpec load_scene(const std::string& file_or_name) {
  if (is_builtin_scene(file_or_name)) return builtin_scene(file_or_name);
  try {
    return load_scene_file(file_or_name);
  } catch (const InputError& error) {
    // "paper-fig7" is more likely a mistyped built-in than a missing file: say both.
    const bool unreadable = error.field().empty() && error.reason().starts_with("cannot read file");
    if (!unreadable || !looks_like_scene_name(file_or_name)) throw;
    throw InputError(file_or_name, "", error.reason() + "; it is not a built-in scene either (built-ins: " +
                                           builtin_names() + ")");
  }
}

}  // namespace clothsim
