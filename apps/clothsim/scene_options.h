// The options that choose a scene and override its fields, shared by `clothsim run` and
// `clothsim view` so that both read a scene and its flags the same way, with the same messages.
//
// SCENE (a file or a built-in name) or --paper-args picks the scene; --material replaces its
// material (at the scene's spacing), before the other flags so that they can override its values;
// --set KEY=VALUE sets any registry field (scene/parameters.h), in order; then the named field
// flags (--integrator,
// --gravity, ...) each set one field. Every value goes through set_scene_field with the flag as
// its source, so "--fps: field 'output.fps': must be ..." reads like the scene file's message.
// A subcommand registers only the field flags that mean something to it (FieldFlagSet).
#pragma once

#include <array>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

#include "scene/scene.h"

namespace clothsim::cli {

// A flag that sets one scene field, by its registry key.
struct FieldFlag {
  std::string_view flag;
  std::string_view key;
  std::string_view value_name;
  std::string_view what;  // help text; the allowed range is appended from the registry
};

inline constexpr std::array<FieldFlag, 17> kFieldFlags = {{
    {"--duration", "output.duration", "SECONDS", "simulated time to run"},
    {"--fps", "output.fps", "N", "frames written per simulated second"},
    {"--integrator", "integrator.method", "METHOD",
     "time integrator: rkf45, rk4, symplectic-euler, implicit-euler or imex"},
    {"--rtol", "integrator.relative_tolerance", "X", "RKF45 and imex relative error tolerance"},
    {"--atol", "integrator.absolute_tolerance", "X", "RKF45 and imex absolute error tolerance (m, m/s)"},
    {"--time-step", "integrator.time_step", "SECONDS",
     "step of rk4, symplectic-euler and implicit-euler; first trial step of rkf45 and imex"},
    {"--gravity", "environment.gravity", "X,Y,Z", "gravitational acceleration, m/s^2"},
    {"--anchor", "anchors", "PRESET", "anchored particles: center, corners, edge-corners or none"},
    {"--threads", "threads", "N", "worker threads; 0 chooses from the lattice size and the idle cores"},
    {"--rest-energy", "output.rest_kinetic_energy", "JOULES", "kinetic energy below which --until-rest stops"},
    // on|off rather than the registry's true|false: a switch reads better on the command line.
    {"--self-collision", "collision.self", "on|off", "self-collision: keep the sheet from passing through itself"},
    {"--thickness", "collision.thickness", "M", "collision thickness: distance kept from colliders (and the sheet), m"},
    {"--checkpoint-every", "output.checkpoint_every", "SECONDS",
     "write a checkpoint every this much simulated time, for --resume (0: none)"},
    {"--export", "output.export", "LIST",
     "files for other tools, comma-separated: pc2 (animation.pc2 and rest.obj), obj-sequence (frames/*.obj), gltf "
     "(final.glb), gltf-animation (animation.glb: every frame, as glTF morph targets); none"},
    {"--backend", "backend", "cpu|vulkan",
     "where the steps run: cpu (every feature), or vulkan (rkf45, rk4, symplectic-euler and implicit-euler on a "
     "Vulkan device, with tearing, plasticity, creasing and obstacles; self-collision runs on the cpu between the "
     "device's steps, imex on the cpu only: docs/gpu.md)"},
    {"--device", "device", "N", "the Vulkan device of --backend vulkan, as 'clothsim devices' lists them"},
    {"--precision", "precision", "float64|float32|auto",
     "arithmetic of the forces: float64, float32 (the vulkan default; on the cpu, float32 springs with a float64 "
     "state, for rkf45, rk4 and symplectic-euler), or auto (the cpu default: float32 where rkf45's tolerances are "
     "both 1e-6 or looser, else float64, and on the cpu float32 only for the frames whose forces agree with "
     "float64's to a quarter of atol: docs/performance.md)"},
}};

// Which of kFieldFlags a subcommand offers, by flag name, with optional help text replacing the
// table's (the viewer's --fps means something else than run's).
struct FieldFlagChoice {
  std::string_view flag;
  std::string_view what = {};  // empty: the table's help text
};

struct SceneOptions {
  CLI::App* app = nullptr;
  std::string command;     // "run", "view": names the subcommand in messages
  std::string scene;       // file or built-in name
  std::string paper_args;  // the paper's ten numbers
  std::string material;    // --material: a preset name or a JSON object, applied before --set
  std::array<std::string, kFieldFlags.size()> field_values;
  std::vector<std::string> assignments;  // --set KEY=VALUE, in order

  // True when the option (a flag such as "--fps", or the positional "SCENE") was given.
  bool given(std::string_view flag) const { return app->count(std::string(flag)) > 0; }
};

// Registers SCENE, --paper-args, --set and the chosen field flags on `app`.
void add_scene_options(CLI::App& app, SceneOptions& options, std::initializer_list<FieldFlagChoice> field_flags);
// The same with every field flag (run, sweep).
void add_scene_options(CLI::App& app, SceneOptions& options);

// The scene with every flag applied and checked (validate_scene); throws InputError. `extra`, if
// given, applies a subcommand's own overrides after the field flags and returns whether it
// changed anything (the source then reads "... with the command-line flags").
SceneSpec make_scene(const SceneOptions& options, const std::function<bool(SceneSpec&)>& extra = {});

}  // namespace clothsim::cli
