// Scenes: everything needed to reproduce a run, read from a JSON file, from the paper's
// 10-number argument vector, or from the built-in library.
//
// SceneSpec is plain data with in-class defaults. This header declares it and its readers and
// writer (scene.cpp); the built-in library is builtin_scenes.h, the cross-field checks
// validate_scene.h, and the ClothModel and initial ClothState a scene builds scene_model.h.
// Parsing and validation report bad input as InputError naming the file, the dotted field and
// the allowed range, and happen before any output is created. docs/scene-format.md documents the
// format.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "integrators/integrator.h"
#include "model/anchor.h"
#include "model/cloth_model.h"
#include "model/collider.h"
#include "model/initial_conditions.h"
#include "model/material.h"
#include "sim/backend.h"

namespace clothsim {

// An anchored particle named by lattice coordinates. The path's origin defaults to the particle's
// rest position unless `origin_given`.
struct AnchorSpec {
  int row = 0;
  int col = 0;
  AnchorPath path;
  bool origin_given = false;
  // When the anchor lets go, s, in [0, output.duration); +inf: never (Anchor::release_time).
  double release_time = std::numeric_limits<double>::infinity();
};

// A cut made before the run (a notch): every connector crossed by the segment between two
// rest-lattice points (row, col), in particle spacings (model/lattice_cuts.h), is broken at t = 0.
// (10.5, -1) to (10.5, 4) cuts the first 5 columns between rows 10 and 11.
struct CutSpec {
  std::array<double, 2> from{};
  std::array<double, 2> to{};
  bool operator==(const CutSpec&) const = default;
};

// An obstacle as the scene gives it ("colliders" in the file; model/collider.h). A mesh is read
// when the scene is read, so that a missing or malformed file fails before any output exists;
// `collider.mesh` holds it scaled and translated, and `collider.mesh_file` the path it was read
// from. The fields below keep the file's own values, so scene_to_json() writes back what was
// written rather than the mesh's world coordinates.
struct ColliderSpec {
  Collider collider;
  std::string mesh_file;    // mesh: "file" as written, relative to the scene file's folder
  double mesh_scale = 1.0;  // mesh: uniform scale applied to the file's coordinates
  Vec3 mesh_translate;      // mesh: m, added after scaling
};

// Files a run writes besides its own (run/run_exports.h, docs/exports.md), for other tools:
// "pc2" (animation.pc2 + rest.obj), "obj-sequence" (frames/frame_NNNNNN.obj), "gltf" (final.glb)
// and "gltf-animation" (animation.glb).
enum class ExportFormat : std::uint8_t {
  pc2,             // a PC2 point cache of the particles, every saved frame, and its rest.obj
  obj_sequence,    // one OBJ mesh per saved frame
  gltf,            // the last frame as a binary glTF 2.0 file
  gltf_animation,  // every saved frame in one binary glTF 2.0 file, a morph target each
};

std::string_view to_string(ExportFormat format);
// "pc2", "obj-sequence", "gltf", "gltf-animation"; false for any other text (`format` is then unchanged).
bool parse_export_format(std::string_view text, ExportFormat& format);

struct OutputSettings {
  double duration = 20.0;             // simulated time to run, s; with until_rest, the upper limit
  int fps = 60;                       // frames written per simulated second
  bool until_rest = false;            // stop once the sheet is at rest (below)
  double rest_kinetic_energy = 1e-6;  // J
  // At rest: the kinetic energy below rest_kinetic_energy at every frame for this long, s. A
  // single frame is not enough: a sheet bouncing as a whole passes through zero kinetic energy at
  // every turning point (paper-fig4 does, every 3 s, with hundreds of joules in the bounce).
  double rest_duration = 1.0;
  // Checkpoints (run/run_checkpoints.h): one after the first frame at least this much simulated
  // time after the previous one, s; 0: none.
  double checkpoint_every = 0.0;
  // Extra files for other tools ("output.export"), each format at most once, in the order given.
  std::vector<ExportFormat> exports;
};

struct SceneSpec {
  std::string name = "untitled";
  std::string description;
  LatticeDef lattice;
  // The material the lattice's mass, spring constants, rest angles and limits were last set from
  // (set_scene_material), or none: the lattice's own constants, the paper's by default. A record:
  // the lattice holds the values the model is built from, including any key set after the
  // material (such keys override it).
  std::optional<MaterialDef> material{};
  Environment environment;
  std::vector<AnchorSpec> anchors;
  std::vector<CutSpec> cuts;            // notches cut before the run
  std::vector<ColliderSpec> colliders;  // obstacles
  CollisionSettings collision;
  InitialConditions initial;
  // time_step 0: none set, the method's own (scene_integrator()).
  IntegratorSettings integrator{.time_step = 0.0};
  OutputSettings output;
  int threads = 0;  // 0: choose from the lattice size (core/parallel.h)
  // Where the steps run: "backend" ("cpu" or "vulkan"), "device" (the Vulkan device) and
  // "precision" ("float64", "float32" or "auto"; absent: the backend's own) (sim/backend.h).
  BackendSettings backend;
};

// The scene's integrator settings as its simulation runs them: a time step left at 0 becomes the
// method's own, the frame step 1 / output.fps for implicit Euler (a method made for frame-sized
// steps; the collision stage still ends a step at an approaching impact) and kDefaultTimeStep for
// the others (explicit methods' step, RKF45's and imex's first trial step).
IntegratorSettings scene_integrator(const SceneSpec& spec);

// Reads and validates a scene file. Throws InputError naming `path`. Mesh files of colliders are
// found relative to the scene file's folder.
SceneSpec load_scene_file(const std::string& path);
// Parses and validates JSON text; `source` names it in messages. Mesh files of colliders are
// found relative to `base_folder` ("" is the working directory).
SceneSpec parse_scene(std::string_view json_text, const std::string& source, const std::string& base_folder = "");
// The paper's argument vector "rows,cols,mass,k_adj,c_adj,k_opp,c_opp,k_conn,c_conn,length"
// with the centre particle anchored at the origin (as in all the paper's runs).
SceneSpec scene_from_paper_args(std::string_view text, const std::string& source);

// Named anchor sets: "center", "corners", "none"; also "edge-corners" ((0, 0) and (0, cols-1)).
// Replaces `anchors` and returns true, or returns false for an unknown name.
bool parse_anchor_preset(std::string_view text, const LatticeDef& lattice, std::vector<AnchorSpec>& anchors);

// Sets one field by its dotted key ("lattice.rows", "output.fps", "integrator.method", ...) from
// text, with the same validation as the scene file; `source` names the flag in messages.
// Vectors are written "x,y,z", booleans "true"/"false", "anchors" takes a preset name or a JSON
// list, "colliders" a JSON list (mesh files found from the working directory), "paper_args" the
// ten numbers, limits a number or "none" (never), "material" a preset name or a JSON object of
// material fields. Only the field itself is checked: call
// validate_scene() after the last one (cross-field rules). An anchor preset is resolved against
// the lattice as it is when the preset is set, so set lattice.rows and lattice.cols first; a
// material is applied at the spacing as it is then, so set lattice.spacing first.
void set_scene_field(SceneSpec& spec, std::string_view key, std::string_view value, const std::string& source);

// Sets the lattice's particle mass, spring constants, rest angles and spring limits from
// `material` at the lattice's current spacing (rows, cols and spacing stay), and records it in
// spec.material. Throws InputError naming `source` for an invalid material.
void set_scene_material(SceneSpec& spec, const MaterialDef& material, const std::string& source);

// The complete scene as JSON in the file format; parse_scene(scene_to_json(s)) == s.
nlohmann::json scene_to_json(const SceneSpec& spec);
}  // namespace clothsim
