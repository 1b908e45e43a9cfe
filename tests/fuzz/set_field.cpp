// Fuzz target: `--set KEY=VALUE` values (src/scene/scene.h, set_scene_field), as `clothsim run
// SCENE --set ...` applies them. The input is one assignment per line; each line is handled as
// one --set argument is (apps/clothsim/scene_options.cpp): split at its first '=', applied in
// order to the paper-fig5 scene, then the cross-field check (validate_scene).
//
// A scene the flags leave valid must also be writable and read back the same (its scene.json,
// scene.h: parse_scene(scene_to_json(s)) == s), and small ones are built into a model and an
// initial state, as a run does next. "colliders" mesh files are found from the working
// directory, as on the command line.
#include <nlohmann/json.hpp>
#include <string>

#include "fuzz_target.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene/scene_model.h"
#include "scene/validate_scene.h"

namespace {

constexpr long long kLargestBuiltLattice = 4096;  // particles

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace clothsim;
  std::string_view text = fuzz::as_text(data, size);
  fuzz::accept_input_error([&] {
    SceneSpec spec = builtin_scene("paper-fig5");
    while (!text.empty()) {
      const std::size_t newline = text.find('\n');
      const std::string_view assignment = text.substr(0, newline);
      text = newline == std::string_view::npos ? std::string_view{} : text.substr(newline + 1);
      const std::size_t equals = assignment.find('=');
      // The tool rejects these before set_scene_field (scene_options.cpp).
      if (equals == std::string_view::npos || equals == 0) throw InputError("--set", "", "expects KEY=VALUE");
      set_scene_field(spec, assignment.substr(0, equals), assignment.substr(equals + 1), "--set");
    }
    validate_scene(spec, "paper-fig5 with the command-line flags");
    const nlohmann::json written = scene_to_json(spec);
    const SceneSpec again = parse_scene(written.dump(2), "scene.json", "");
    const nlohmann::json written_again = scene_to_json(again);
    if (written_again != written)
      std::fprintf(stderr, "changed: %s\n", nlohmann::json::diff(written, written_again).dump().c_str());
    FUZZ_CHECK(written_again == written);
    if (static_cast<long long>(spec.lattice.rows) * spec.lattice.cols <= kLargestBuiltLattice) {
      const ClothModel model = build_model(spec);
      const ClothState state = build_initial_state(model, spec);
      FUZZ_CHECK(state.position.size() == model.particle_count());
    }
  });
  return 0;
}
