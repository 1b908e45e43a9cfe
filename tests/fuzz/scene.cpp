// Fuzz target: scene files (src/scene/scene.h, parse_scene), as `clothsim run FILE` and
// `clothsim validate FILE` read them. The input is the file's text.
//
// Accepted scenes must also round-trip (scene.h: parse_scene(scene_to_json(s)) == s): the scene
// written back (as a run writes scene.json) reads again to the same JSON. Small ones are built
// into a model and an initial state, as a run does next; large lattices are left out so that an
// input costs milliseconds and not the memory of a 4096 x 4096 sheet.
//
// Mesh colliders are read relative to tests/fuzz/scene/meshes/ (CLOTHSIM_FUZZ_MESH_FOLDER), so
// seeds can name the meshes there.
#include <nlohmann/json.hpp>
#include <string>

#include "fuzz_target.h"
#include "scene/scene.h"
#include "scene/scene_model.h"

namespace {

constexpr long long kLargestBuiltLattice = 4096;  // particles

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace clothsim;
  const std::string_view text = fuzz::as_text(data, size);
  const std::string folder = CLOTHSIM_FUZZ_MESH_FOLDER;
  fuzz::accept_input_error([&] {
    const SceneSpec spec = parse_scene(text, "fuzz.json", folder);
    const nlohmann::json written = scene_to_json(spec);
    const SceneSpec again = parse_scene(written.dump(2), "fuzz.json written back", folder);
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
