// The smallest program built against an installed clothsim (examples/consumer/CMakeLists.txt,
// docs/library.md): loads a scene (a built-in name or a scene file, as `clothsim run` takes it),
// builds its sheet, steps it to t = 1 s and prints the time and the energies. The figures are the
// library's alone, so this prints the same bytes wherever it is built against the same clothsim
// (tests/install compares it with the copy built in the clothsim tree).
#include <cstdio>
#include <exception>
#include <string>
#include <utility>

#include "core/error.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene/scene_model.h"
#include "sim/simulation.h"

int main(int argc, char** argv) {
  using namespace clothsim;
  const std::string scene_name = argc > 1 ? argv[1] : "paper-fig5";
  try {
    const SceneSpec spec = load_scene(scene_name);  // throws InputError naming what is wrong
    ClothModel model = build_model(spec);
    ClothState initial = build_initial_state(model, spec);
    SimulationSettings settings;
    settings.integrator = spec.integrator;
    settings.threads = spec.threads;
    Simulation simulation(std::move(model), std::move(initial), settings);

    if (!simulation.advance_to(1.0)) {
      std::fprintf(stderr, "consumer: %s\n", simulation.failure()->message.c_str());
      return 1;
    }
    const EnergyReport energy = simulation.energy();
    std::printf("scene %s: %zu particles, t = %.17g s, %llu steps\n", spec.name.c_str(),
                simulation.model().particle_count(), simulation.state().time,
                static_cast<unsigned long long>(simulation.integrator_stats().accepted_steps));
    std::printf("energy %.17g J (kinetic %.17g J, gravitational %.17g J)\n", energy.total(), energy.kinetic,
                energy.gravitational);
  } catch (const InputError& error) {
    std::fprintf(stderr, "consumer: %s\n", error.what());
    return 2;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "consumer: %s\n", error.what());
    return 3;
  }
  return 0;
}
