// The built-in scenes (builtin_scenes.h). The paper's figures are built from its own 10-number
// argument vectors through scene_from_paper_args(), the same path a user's `paper_args` takes.
// The "paper material" of the other scenes is LatticeDef's defaults, which are the constants of
// those figures.
#include "scene/builtin_scenes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "model/material.h"
#include "scene/scene.h"
#include "scene/scene_model.h"

namespace clothsim {
namespace {

SceneSpec paper_scene(std::string_view name, std::string_view arguments, std::string_view description) {
  SceneSpec spec = scene_from_paper_args(arguments, "built-in scene '" + std::string(name) + "'");
  spec.name = std::string(name);
  spec.description = std::string(description);
  return spec;
}

// Figure 4 with self-collision on: the paper had none and says its results hold only
// while the sheet does not pass through itself. The folds of this sheet never come within the
// thickness of each other, so the run is the paper's, bit for bit, with the check that it is.
SceneSpec paper_fig4() {
  SceneSpec spec = paper_scene("paper-fig4", "21,21,1,4,1,1400,200,80,5,1",
                               "The paper's Figure 4: a 21 x 21 sheet held by its centre particle at the origin; at "
                               "rest it folds in on itself. Paper arguments [21, 21, 1, 4, 1, 1400, 200, 80, 5, 1]; "
                               "self-collision on (thickness 5 mm).");
  spec.collision.self = true;
  return spec;
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
  spec.description = "A 25 x 25 sheet of the paper's material hung by the two corners of row 0, draping under gravity.";
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
  spec.lattice.spacing = 1.0 / 127.0;
  set_scene_material(spec, cotton_material(), "built-in scene 'cotton-drape'");
  parse_anchor_preset("edge-corners", spec.lattice, spec.anchors);
  spec.integrator.kind = IntegratorKind::implicit_euler;
  spec.integrator.time_step = 1.0 / 60.0;
  spec.output.duration = 5.0;
  return spec;
}

// Sheets that change (tearing, permanent stretching, creasing): small lattices of a physical material, driven by
// keyframed anchors, integrated by implicit Euler at a step of 1 ms (paper and film are far too
// stiff for an explicit method at these spacings: a connector's k/m is near 5e10 s^-2 for paper).

MaterialDef preset(std::string_view name) { return *find_material_preset(name); }

// A w x w sheet of `material` on an n x n lattice (spacing w / (n - 1)).
SceneSpec material_sheet(std::string_view name, std::string_view material, int n, double width) {
  SceneSpec spec;
  spec.name = std::string(name);
  spec.lattice.rows = n;
  spec.lattice.cols = n;
  spec.lattice.spacing = width / (n - 1);
  set_scene_material(spec, preset(material), "built-in scene '" + spec.name + "'");
  spec.integrator.kind = IntegratorKind::implicit_euler;
  spec.integrator.time_step = 1e-3;
  return spec;
}

// Every particle of lattice row `row` anchored on `path` (its origin: each particle's rest position).
void anchor_row(SceneSpec& spec, int row, const AnchorPath& path, double release_time = SpringLimits::kNever) {
  for (int col = 0; col < spec.lattice.cols; ++col) {
    AnchorSpec anchor{row, col, path, false};
    anchor.release_time = release_time;
    spec.anchors.push_back(anchor);
  }
}

AnchorPath keyframes(std::vector<AnchorKey> keys) {
  AnchorPath path;
  path.kind = AnchorPathKind::keyframes;
  path.keys = std::move(keys);
  return path;
}

SceneSpec tear_pull() {
  SceneSpec spec = material_sheet("tear-pull", "paper", 21, 0.2);
  spec.description =
      "A 20 cm square of office paper (21 x 21) with a 5-spacing notch in its left edge, held along two opposite "
      "edges which keyframes pull 1 cm apart each in 0.5 s: the paper yields, then tears from the notch across "
      "into two pieces (connectors break near 2 % strain). With --set springs.connector.break_strain=1000 it "
      "stretches but stays whole. Implicit Euler, 1 ms, 1 s.";
  const int last = spec.lattice.rows - 1;
  anchor_row(spec, 0, keyframes({{0.0, {}}, {0.5, {0.0, 0.0, -0.01}}}));
  anchor_row(spec, last, keyframes({{0.0, {}}, {0.5, {0.0, 0.0, 0.01}}}));
  // A notch, as tear tests cut one (single-edge-notch tension): without it a uniform pull breaks
  // springs scattered over the sheet, as in a bundle of fibres, and no crack runs across.
  const double middle = (spec.lattice.rows - 1) / 2.0 - 0.5;
  spec.cuts.push_back({{middle, -1.0}, {middle, 4.5}});
  spec.output.duration = 1.0;
  return spec;
}

SceneSpec paper_crease() {
  SceneSpec spec = material_sheet("paper-crease", "paper", 21, 0.2);
  spec.description =
      "A 20 cm square of office paper (21 x 21) without gravity: rows 0 and 1 held, rows 19 and 20 turned over "
      "on keyframes (180 degrees in 0.5 s, about the middle of the sheet) to fold it in half, held, and let go "
      "at 0.8 s. The fold creases (opposite yield angle 20 degrees): the sheet stays folded. Implicit Euler, "
      "1 ms, 2 s.";
  spec.environment.gravity = {0.0, 0.0, 0.0};
  const int last = spec.lattice.rows - 1;
  const double gap = spec.lattice.spacing;  // between the two layers once folded
  anchor_row(spec, 0, AnchorPath{});
  anchor_row(spec, 1, AnchorPath{});
  // Rows last-1 and last turn rigidly about the line y = gap / 2, z = 0 (parallel to x), up and
  // over: a rest point (0, z) is at (gap/2 - gap/2 cos a + z sin a, gap/2 sin a... ) written out
  // below with a from 0 to pi. Keys every 5 degrees keep the turned pair's connectors within 0.1 %
  // of their length on the chords between keys (1 - cos 2.5 degrees).
  constexpr int kSteps = 36;
  constexpr double kTurnTime = 0.5;
  for (int row = last - 1; row <= last; ++row) {
    const double z = lattice_rest_position(spec.lattice, row, 0).z;
    std::vector<AnchorKey> keys;
    for (int step = 0; step <= kSteps; ++step) {
      const double angle = std::numbers::pi * step / kSteps;
      // Relative to the axis the point starts at (-gap/2, z) in (y, z); turned by -angle about x.
      const double y_turned = -0.5 * gap * std::cos(angle) + z * std::sin(angle);
      const double z_turned = 0.5 * gap * std::sin(angle) + z * std::cos(angle);
      keys.push_back({kTurnTime * step / kSteps, {0.0, 0.5 * gap + y_turned, z_turned - z}});
    }
    anchor_row(spec, row, keyframes(keys), 0.8);
  }
  spec.output.duration = 2.0;
  return spec;
}

SceneSpec film_stretch() {
  SceneSpec spec = material_sheet("film-stretch", "plastic-film", 21, 0.2);
  spec.description =
      "A 20 cm square of polyethylene film (21 x 21) without gravity: row 0 held, row 20 pulled 4 cm (20 %) in "
      "0.5 s on keyframes and let go at 0.7 s. The film yields at 5 % and stays about 14 % longer. Implicit "
      "Euler, 1 ms, 1.5 s.";
  spec.environment.gravity = {0.0, 0.0, 0.0};
  anchor_row(spec, 0, AnchorPath{});
  anchor_row(spec, spec.lattice.rows - 1, keyframes({{0.0, {}}, {0.5, {0.0, 0.0, 0.04}}}), 0.7);
  spec.output.duration = 1.5;
  return spec;
}

SceneSpec cloth_shake() {
  SceneSpec spec = material_sheet("cloth-shake", "cotton", 21, 0.4);
  spec.description =
      "A 40 cm square of cotton shirting (21 x 21) waved hard by one edge: row 0 moves up and down 10 cm at "
      "3 Hz (peak acceleration 3.6 g). Cloth neither tears nor keeps a stretch: no spring breaks, no rest "
      "value changes. Implicit Euler, 1 ms, 2 s.";
  AnchorPath wave;
  wave.kind = AnchorPathKind::sinusoid;
  wave.amplitude = {0.0, 0.1, 0.0};
  wave.frequency = 3.0;
  anchor_row(spec, 0, wave);
  spec.output.duration = 2.0;
  return spec;
}

// Obstacles: cotton dropped onto a shape, with a floor below.

ColliderSpec collider_spec(const Collider& collider) {
  ColliderSpec spec;
  spec.collider = collider;
  return spec;
}

Collider floor_plane(double height) {
  Collider floor;
  floor.shape = ColliderShape::plane;
  floor.point = {0.0, height, 0.0};
  floor.normal = {0.0, 1.0, 0.0};
  return floor;
}

SceneSpec drape_sphere() {
  SceneSpec spec = material_sheet("drape-sphere", "cotton", 41, 1.0);
  spec.description =
      "A 1 m square of cotton shirting (41 x 41) dropped from 10 cm above a sphere of radius 0.3 m: it drapes "
      "over the sphere in folds, the corners hanging towards the floor 0.8 m below the sheet. Implicit Euler, "
      "1 ms, 3 s.";
  Collider sphere;
  sphere.shape = ColliderShape::sphere;
  sphere.center = {0.0, -0.4, 0.0};
  sphere.radius = 0.3;
  spec.colliders.push_back(collider_spec(sphere));
  spec.colliders.push_back(collider_spec(floor_plane(-0.8)));
  spec.output.duration = 3.0;
  return spec;
}

SceneSpec sphere_sweep() {
  SceneSpec spec = material_sheet("sphere-sweep", "cotton", 21, 0.5);
  spec.description =
      "A 50 cm square of cotton shirting (21 x 21) hung by its row 0, which falls and swings down; a sphere of "
      "radius 10 cm then sweeps through the hanging sheet at 1 m/s along +z, about 25 cm below the held edge, "
      "and pushes it aside. Implicit Euler, 1 ms, 3 s.";
  anchor_row(spec, 0, AnchorPath{});
  Collider sphere;
  sphere.shape = ColliderShape::sphere;
  sphere.center = {0.0, -0.25, -1.5};
  sphere.radius = 0.1;
  sphere.path.kind = AnchorPathKind::linear;
  sphere.path.velocity = {0.0, 0.0, 1.0};  // crosses the sheet's plane (z = -0.25) at t = 1.25 s
  spec.colliders.push_back(collider_spec(sphere));
  spec.output.duration = 3.0;
  return spec;
}

SceneSpec tablecloth() {
  SceneSpec spec = material_sheet("tablecloth", "cotton", 41, 1.0);
  spec.description =
      "A 1 m square of cotton shirting (41 x 41) dropped 5 cm onto a square table 0.7 m wide (a box from the "
      "floor to its top): it lies flat on the top and the 15 cm overhang hangs down the sides, folding at the "
      "corners. Implicit Euler, 1 ms, 3 s.";
  Collider table;
  table.shape = ColliderShape::box;
  table.center = {0.0, -0.425, 0.0};
  table.half_extents = {0.35, 0.375, 0.35};  // top at y = -0.05, bottom on the floor at y = -0.8
  spec.colliders.push_back(collider_spec(table));
  spec.colliders.push_back(collider_spec(floor_plane(-0.8)));
  spec.output.duration = 3.0;
  return spec;
}

// pile: the sheet folds onto itself on the ground, the scene that self-collision is measured on
// (docs/performance.md, "Collisions"). A built-in scene cannot start the sheet hanging (the lattice starts flat, and
// anchors name particles by row and column, so they would not follow `--set lattice.rows=...`).
// Instead the flat sheet falls across a thin frictionless rod that lies off its middle: the longer
// side pulls it off the rod, and it falls 0.7 m onto the floor, where it lands as a column and
// buckles into folds that lie on each other, parallel to the rod. Only colliders set the scene up,
// so any lattice size runs it: `--set lattice.rows=200 --set lattice.cols=200` is a 4 m sheet of
// the same cotton at the same spacing, and `--set lattice.spacing=0.005025 --set material=cotton`
// after them keeps 1 m (the material must be set again at the new spacing). Tested (50 x 50): at
// least 3 folds along the middle lattice column, with and without self-collision.
SceneSpec pile() {
  SceneSpec spec = material_sheet("pile", "cotton", 50, 1.0);
  spec.description =
      "A 1 m square of cotton shirting (50 x 50) dropped across a thin frictionless rod 15 cm off its middle: the "
      "longer side pulls it off the rod, and it falls 0.7 m to the floor, where it folds onto itself. "
      "Self-collision on, thickness 2 mm (below half the spacing up to 200 x 200 for 1 m); with --self-collision "
      "off the folds pass through each other. Implicit Euler, 1 ms, 3 s.";
  Collider rod;
  rod.shape = ColliderShape::capsule;
  rod.a = {-0.6, -0.05, 0.15};  // along x, under the sheet 15 cm from its middle, a little longer than it
  rod.b = {0.6, -0.05, 0.15};
  rod.radius = 0.02;
  // Frictionless, so that the sheet slides off it; held by friction, it would hang there.
  rod.friction = 0.0;
  spec.colliders.push_back(collider_spec(rod));
  spec.colliders.push_back(collider_spec(floor_plane(-1.25)));
  // Thin, so that folds can lie close: self-collision needs it below half the spacing, which is
  // 2.5 mm for a 1 m sheet at 200 x 200.
  spec.collision.self = true;
  spec.collision.thickness = 0.002;
  spec.output.duration = 3.0;
  return spec;
}

// tear-crumple: the paper's three goals (tearing, permanent stretching, creasing) and both kinds of
// contact at once. A soft paper thrown down onto a ball wraps it, yields where it is pulled round,
// creases where it folds, tears on from a notch cut in its edge and folds onto itself, never
// crossing itself on either backend (on the device, implicit Euler's own self pass: docs/gpu.md).
SceneSpec tear_crumple() {
  SceneSpec spec;
  spec.name = "tear-crumple";
  spec.description =
      "A 30 cm square of soft paper (25 x 25; 30 g/m^2, 2 kN/m, yielding at 1 % and breaking near 4 % strain, "
      "creasing past 20 degrees) with a notch in one edge, thrown down at 4 m/s onto a ball of radius 5 cm: it "
      "wraps the ball, tears on from the notch, creases and folds onto itself (self-collision on). Implicit "
      "Euler, 1 ms, 0.6 s.";
  spec.lattice.rows = 25;
  spec.lattice.cols = 25;
  spec.lattice.spacing = 0.3 / 24.0;
  MaterialDef soft_paper;
  soft_paper.name = "soft-paper";
  soft_paper.areal_density = 0.03;
  soft_paper.stretch_stiffness = 2000.0;
  soft_paper.shear_stiffness = 600.0;
  soft_paper.bending_rigidity = 2e-6;
  soft_paper.damping_time = 1e-3;
  soft_paper.break_strain = 0.04;
  soft_paper.break_strain_variation = 0.2;
  soft_paper.yield_strain = 0.01;
  soft_paper.hardening = 0.3;
  soft_paper.opposite_yield_angle = 20.0 / 180.0 * std::numbers::pi;  // as scene/ converts 20 degrees
  set_scene_material(spec, soft_paper, "built-in scene 'tear-crumple'");
  // The notch: the first 8 columns cut between rows 11 and 12.
  spec.cuts.push_back({{11.5, -1.0}, {11.5, 7.0}});
  spec.initial.velocity = {0.0, -4.0, 0.0};
  Collider ball;
  ball.shape = ColliderShape::sphere;
  ball.center = {0.02, -0.1, 0.01};  // a little off the sheet's centre, so that it wraps unevenly
  ball.radius = 0.05;
  ball.friction = 0.5;
  spec.colliders.push_back(collider_spec(ball));
  Collider floor = floor_plane(-0.2);
  floor.friction = 0.5;
  spec.colliders.push_back(collider_spec(floor));
  spec.collision.self = true;
  spec.collision.thickness = 0.002;
  spec.integrator.kind = IntegratorKind::implicit_euler;
  spec.integrator.time_step = 1e-3;
  spec.output.duration = 0.6;
  return spec;
}

struct BuiltinEntry {
  std::string_view name;
  SceneSpec (*make)();
};

constexpr std::array<BuiltinEntry, 15> kBuiltins = {{
    {"paper-fig4", paper_fig4},
    {"paper-fig5", paper_fig5},
    {"paper-fig6", paper_fig6},
    {"drape-corners", drape_corners},
    {"free-spin", free_spin},
    {"cotton-drape", cotton_drape},
    {"tear-pull", tear_pull},
    {"paper-crease", paper_crease},
    {"film-stretch", film_stretch},
    {"cloth-shake", cloth_shake},
    {"drape-sphere", drape_sphere},
    {"tablecloth", tablecloth},
    {"sphere-sweep", sphere_sweep},
    {"pile", pile},
    {"tear-crumple", tear_crumple},
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
    throw InputError(file_or_name, "",
                     error.reason() + "; it is not a built-in scene either (built-ins: " + builtin_names() + ")");
  }
}

}  // namespace clothsim
