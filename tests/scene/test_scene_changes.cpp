// The scene keys of issue 7: spring limits, keyframed anchors, release_time and materials.
// Each is parsed, set from --set text, validated (InputError naming the file, the field and what
// is allowed) and written back by scene_to_json so that reading it again gives the same scene.
#include <gtest/gtest.h>

#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "model/material.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene/scene_model.h"
#include "scene/validate_scene.h"
#include "test_helpers.h"

namespace clothsim {
namespace {

using testing::expect_input_error;
using testing::expect_same_scene;

constexpr double kNever = std::numeric_limits<double>::infinity();

SceneSpec round_trip(const SceneSpec& spec) { return parse_scene(scene_to_json(spec).dump(), "written.json"); }

TEST(SpringLimitKeys, DefaultToNeverAndParse) {
  const SceneSpec defaults = parse_scene("{}", "s.json");
  EXPECT_EQ(defaults.lattice.limits, SpringLimits{});
  const SceneSpec spec = parse_scene(R"({"springs": {
      "connector": {"break_strain": 0.3, "break_strain_variation": 0.25, "yield_strain": 0.1, "hardening": 0.5},
      "adjacent": {"yield_angle_deg": 90}, "opposite": {"yield_angle_deg": null}}})",
                                     "s.json");
  EXPECT_EQ(spec.lattice.limits.break_strain, 0.3);
  EXPECT_EQ(spec.lattice.limits.break_strain_variation, 0.25);
  EXPECT_EQ(spec.lattice.limits.yield_strain, 0.1);
  EXPECT_EQ(spec.lattice.limits.hardening, 0.5);
  EXPECT_EQ(spec.lattice.limits.adjacent_yield_angle, std::numbers::pi / 2.0);
  EXPECT_EQ(spec.lattice.limits.opposite_yield_angle, kNever);
  expect_same_scene(round_trip(spec), spec);
  // Never is written as null, and read back as never.
  const nlohmann::json written = scene_to_json(spec);
  EXPECT_TRUE(written["springs"]["opposite"]["yield_angle_deg"].is_null());
  EXPECT_EQ(written["springs"]["connector"]["break_strain"], 0.3);
}

TEST(SpringLimitKeys, SetTakesNumbersAndNone) {
  SceneSpec spec;
  set_scene_field(spec, "springs.connector.break_strain", "0.02", "--set");
  set_scene_field(spec, "springs.opposite.yield_angle_deg", "20", "--set");
  EXPECT_EQ(spec.lattice.limits.break_strain, 0.02);
  EXPECT_EQ(spec.lattice.limits.opposite_yield_angle, 20.0 / 180.0 * std::numbers::pi);
  set_scene_field(spec, "springs.connector.break_strain", "none", "--set");
  EXPECT_EQ(spec.lattice.limits.break_strain, kNever);
  expect_input_error([&] { set_scene_field(spec, "springs.connector.break_strain", "inf", "--set"); },
                     {"--set", "springs.connector.break_strain", "a number in (0, 1e6] or none (never)", "\"inf\""});
}

TEST(SpringLimitKeys, BadValuesNameFileFieldAndRange) {
  expect_input_error([] { parse_scene(R"({"springs": {"connector": {"break_strain": 0}}})", "s.json"); },
                     {"s.json", "springs.connector.break_strain", "(0, 1e6] or none", "got 0"});
  expect_input_error([] { parse_scene(R"({"springs": {"connector": {"break_strain_variation": 1}}})", "s.json"); },
                     {"s.json", "springs.connector.break_strain_variation", "[0, 1)"});
  expect_input_error([] { parse_scene(R"({"springs": {"connector": {"hardening": -1}}})", "s.json"); },
                     {"s.json", "springs.connector.hardening", "[0, 1e6]"});
  expect_input_error([] { parse_scene(R"({"springs": {"opposite": {"yield_angle_deg": 200}}})", "s.json"); },
                     {"s.json", "springs.opposite.yield_angle_deg", "[0, 180]"});
  expect_input_error([] { parse_scene(R"({"springs": {"connector": {"hardening": null}}})", "s.json"); },
                     {"s.json", "springs.connector.hardening", "must be a number, got null"});
  // Yield above break: both fields named.
  expect_input_error(
      [] { parse_scene(R"({"springs": {"connector": {"break_strain": 0.02, "yield_strain": 0.05}}})", "s.json"); },
      {"s.json", "springs.connector.yield_strain", "must be <= springs.connector.break_strain (0.02)", "got 0.05"});
  // An elastic connector (no yield strain) may break at any strain: a breakable cloth.
  EXPECT_EQ(parse_scene(R"({"springs": {"connector": {"break_strain": 0.05}}})", "s.json").lattice.limits.break_strain,
            0.05);
  SceneSpec silk = builtin_scene("drape-corners");
  set_scene_field(silk, "material", "silk", "--material");
  set_scene_field(silk, "springs.connector.break_strain", "0.05", "--set");
  EXPECT_NO_THROW(validate_scene(silk, "--set"));
}

TEST(SpringLimitKeys, BuildModelAppliesThemWithTheScenesSeed) {
  SceneSpec spec = parse_scene(R"({"lattice": {"rows": 5, "cols": 5},
      "springs": {"connector": {"break_strain": 0.3, "break_strain_variation": 0.5, "yield_strain": 0.1},
                  "opposite": {"yield_angle_deg": 90}}, "initial": {"seed": 42}})",
                               "s.json");
  const ClothModel model = build_model(spec);
  EXPECT_EQ(model.limits.variation_seed, 42u);
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    EXPECT_EQ(model.connector_break_strain[e], connector_break_threshold(model.limits, e));
    EXPECT_EQ(model.connector_yield_strain[e], 0.1);
  }
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    EXPECT_EQ(model.radial_yield_angle[r],
              model.radial_kind[r] == RadialKind::opposite ? std::numbers::pi / 2.0 : kNever);
  }
  // A scene without limits builds the unlimited model of the paper.
  const ClothModel paper = build_model(SceneSpec{});
  EXPECT_EQ(paper.connector_break_strain[0], kNever);
  EXPECT_EQ(paper.connector_yield_strain[0], kNever);
}

TEST(KeyframedAnchors, ParseRoundTripAndResolve) {
  const SceneSpec spec = parse_scene(R"({"lattice": {"rows": 3, "cols": 3}, "output": {"duration": 2},
      "anchors": [{"row": 0, "col": 0, "release_time": 1.5,
                   "path": {"type": "keyframes", "keys": [[0, 0, 0, 0], [0.5, 1, 2, 3], [1, 1, 2, 4]]}},
                  {"row": 2, "col": 2, "path": {"type": "keyframes", "keys": [[0.25, 0, -1, 0]]}}]})",
                                     "s.json");
  ASSERT_EQ(spec.anchors.size(), 2u);
  const AnchorPath& path = spec.anchors[0].path;
  EXPECT_EQ(path.kind, AnchorPathKind::keyframes);
  ASSERT_EQ(path.keys.size(), 3u);
  EXPECT_EQ(path.keys[1], (AnchorKey{0.5, {1.0, 2.0, 3.0}}));
  EXPECT_EQ(spec.anchors[0].release_time, 1.5);
  EXPECT_EQ(spec.anchors[1].release_time, kNever);
  expect_same_scene(round_trip(spec), spec);
  EXPECT_FALSE(scene_to_json(spec)["anchors"][1].contains("release_time"));

  const std::vector<Anchor> anchors = resolve_anchors(spec);
  EXPECT_EQ(anchors[0].release_time, 1.5);
  // Offsets are from the particle's rest position, (-1, 0, -1) for (0, 0) with spacing 1.
  EXPECT_EQ(anchors[0].path.position(0.5), (Vec3{0.0, 2.0, 2.0}));
  EXPECT_EQ(build_model(spec).anchors[0].release_time, 1.5);
}

TEST(KeyframedAnchors, BadKeysNameTheKey) {
  const auto scene = [](const std::string& keys) {
    return R"({"anchors": [{"row": 0, "col": 0}, {"row": 1, "col": 1, "path": {"type": "keyframes", "keys": )" + keys +
           "}}]}";
  };
  expect_input_error([&] { parse_scene(scene("[]"), "s.json"); },
                     {"s.json", "anchors[1].path.keys", "at least one key"});
  expect_input_error([&] { parse_scene(scene("[[0, 0, 0, 0], [1, 0, 0, 0], [1, 1, 1, 1]]"), "s.json"); },
                     {"s.json", "anchors[1].path.keys[2]", "strictly increasing time"});
  expect_input_error([&] { parse_scene(scene("[[0, 0, 0]]"), "s.json"); },
                     {"s.json", "anchors[1].path.keys[0]", "4 numbers [t, x, y, z]"});
  expect_input_error([&] { parse_scene(scene("[[0, 0, \"up\", 0]]"), "s.json"); },
                     {"s.json", "anchors[1].path.keys[0][2]", "must be a number"});
  expect_input_error([&] { parse_scene(scene("[[-1, 0, 0, 0]]"), "s.json"); },
                     {"s.json", "anchors[1].path.keys[0][0]", "[0, 1e7]"});
  expect_input_error([] { parse_scene(R"({"anchors": [{"path": {"type": "keyframes"}}]})", "s.json"); },
                     {"s.json", "anchors[0].path.keys", "is required"});
  expect_input_error(
      [] { parse_scene(R"({"anchors": [{"path": {"type": "fixed", "keys": [[0, 0, 0, 0]]}}]})", "s.json"); },
      {"s.json", "anchors[0].path.keys", "belongs to a keyframes path"});
  // Scenes built in code get the same checks.
  SceneSpec spec;
  spec.anchors.push_back(AnchorSpec{});
  spec.anchors[0].path.kind = AnchorPathKind::keyframes;
  expect_input_error([&] { validate_scene(spec, "code"); }, {"code", "anchors[0].path.keys", "at least one key"});
}

TEST(ReleaseTime, MustLieWithinTheRun) {
  expect_input_error([] { parse_scene(R"({"output": {"duration": 2}, "anchors": [{"release_time": 2}]})", "s.json"); },
                     {"s.json", "anchors[0].release_time", "within the run", "[0, output.duration) = [0, 2)", "got 2"});
  expect_input_error([] { parse_scene(R"({"anchors": [{"release_time": -1}]})", "s.json"); },
                     {"s.json", "anchors[0].release_time"});
  EXPECT_EQ(parse_scene(R"({"anchors": [{"release_time": null}]})", "s.json").anchors[0].release_time, kNever);
  // --set output.duration below a release time is caught by validate_scene.
  SceneSpec spec = parse_scene(R"({"anchors": [{"release_time": 10}]})", "s.json");
  set_scene_field(spec, "output.duration", "5", "--duration");
  expect_input_error([&] { validate_scene(spec, "s.json with the command-line flags"); },
                     {"anchors[0].release_time", "[0, 5)"});
}

TEST(SceneMaterial, PresetSetsTheLatticeAtItsSpacingAndKeysBesideItOverride) {
  const SceneSpec spec = parse_scene(R"({"lattice": {"rows": 11, "cols": 11, "spacing": 0.02},
      "material": "paper", "springs": {"connector": {"break_strain": 0.05}}})",
                                     "s.json");
  LatticeDef expected;
  expected.rows = 11;
  expected.cols = 11;
  apply_material(*find_material_preset("paper"), 0.02, expected);
  EXPECT_EQ(spec.lattice.spacing, 0.02);
  EXPECT_EQ(spec.lattice.particle_mass, expected.particle_mass);
  EXPECT_EQ(spec.lattice.connector.stiffness, expected.connector.stiffness);
  EXPECT_EQ(spec.lattice.adjacent.stiffness, expected.adjacent.stiffness);
  EXPECT_EQ(spec.lattice.opposite.damping, expected.opposite.damping);
  EXPECT_EQ(spec.lattice.limits.yield_strain, 0.005);
  EXPECT_EQ(spec.lattice.limits.break_strain, 0.05);  // the override
  ASSERT_TRUE(spec.material.has_value());
  EXPECT_EQ(spec.material->name, "paper");
  expect_same_scene(round_trip(spec), spec);
  EXPECT_EQ(scene_to_json(spec)["material"], "paper");
}

TEST(SceneMaterial, ObjectFieldsInPhysicalUnits) {
  const SceneSpec spec = parse_scene(R"({"lattice": {"spacing": 0.1}, "material": {"name": "felt",
      "areal_density": 0.3, "stretch_stiffness": 2000, "shear_stiffness": 40, "bending_rigidity": 1e-4,
      "damping_time": 0.002, "yield_strain": 0.1, "opposite_yield_angle_deg": 45}})",
                                     "s.json");
  EXPECT_DOUBLE_EQ(spec.lattice.particle_mass, 0.3 * 0.01);
  EXPECT_EQ(spec.lattice.connector.stiffness, 2000.0);
  EXPECT_EQ(spec.lattice.connector.damping, 4.0);
  EXPECT_DOUBLE_EQ(spec.lattice.adjacent.stiffness, 40 * 0.01 / 4);
  EXPECT_EQ(spec.lattice.limits.opposite_yield_angle, std::numbers::pi / 4.0);
  EXPECT_EQ(spec.lattice.limits.break_strain, kNever);
  EXPECT_EQ(spec.material->name, "felt");
  expect_same_scene(round_trip(spec), spec);
}

TEST(SceneMaterial, Errors) {
  expect_input_error([] { parse_scene(R"({"material": "wool"})", "s.json"); },
                     {"s.json", "field 'material'", "cotton, silk, denim, paper, plastic-film", "\"wool\""});
  expect_input_error([] { parse_scene(R"({"material": {"stretch_stiffness": 10}})", "s.json"); },
                     {"s.json", "material.areal_density", "is required"});
  expect_input_error([] { parse_scene(R"({"material": {"areal_density": 0.1, "bendng_rigidity": 1}})", "s.json"); },
                     {"s.json", "material.bendng_rigidity", "did you mean 'material.bending_rigidity'"});
  expect_input_error([] { parse_scene(R"({"material": {"areal_density": -1}})", "s.json"); },
                     {"s.json", "material.areal_density", "(0, 1000]"});
  expect_input_error(
      [] {
        parse_scene(R"({"material": {"areal_density": 0.1, "break_strain": 0.01, "yield_strain": 0.02}})", "s.json");
      },
      {"s.json", "material.yield_strain", "must be <= material.break_strain (0.01)"});
  expect_input_error([] { parse_scene(R"({"material": "paper", "paper_args": [3,3,1,1,1,1,1,1,1,1]})", "s.json"); },
                     {"s.json", "paper_args", "material"});
}

TEST(SceneMaterial, SetFromTheCommandLine) {
  SceneSpec spec = builtin_scene("cotton-drape");
  set_scene_field(spec, "material", "silk", "--material");
  EXPECT_EQ(spec.material->name, "silk");
  EXPECT_EQ(spec.lattice.spacing, 1.0 / 127.0);  // the scene's spacing, rows and cols stay
  EXPECT_EQ(spec.lattice.rows, 128);
  EXPECT_EQ(spec.lattice.connector.stiffness, find_material_preset("silk")->stretch_stiffness);
  set_scene_field(spec, "material", R"({"areal_density": 0.2, "stretch_stiffness": 100})", "--material");
  EXPECT_EQ(spec.material->name, "custom");
  EXPECT_EQ(spec.lattice.connector.stiffness, 100.0);
  expect_input_error([&] { set_scene_field(spec, "material", "velvet", "--material"); },
                     {"--material", "cotton, silk, denim, paper, plastic-film", "\"velvet\""});
  set_scene_field(spec, "material", "none", "--set");
  EXPECT_FALSE(spec.material.has_value());
  EXPECT_EQ(spec.lattice.connector.stiffness, 100.0);
}

TEST(SceneMaterial, WithoutMaterialTheSceneIsThePapers) {
  const SceneSpec spec = parse_scene("{}", "s.json");
  EXPECT_FALSE(spec.material.has_value());
  EXPECT_EQ(spec.lattice.connector.stiffness, 80.0);
  EXPECT_TRUE(scene_to_json(spec)["material"].is_null());
  expect_same_scene(round_trip(spec), spec);
}

TEST(ChangingBuiltins, LoadValidateAndRoundTrip) {
  for (const char* name : {"tear-pull", "paper-crease", "film-stretch", "cloth-shake"}) {
    const SceneSpec spec = builtin_scene(name);
    validate_scene(spec, name);
    EXPECT_TRUE(spec.material.has_value()) << name;
    EXPECT_FALSE(spec.description.empty()) << name;
    EXPECT_LE(spec.output.duration, 2.0) << name;
    expect_same_scene(round_trip(spec), spec);
    EXPECT_NO_THROW(build_model(spec)) << name;
  }
  EXPECT_EQ(builtin_scene("tear-pull").material->name, "paper");
  EXPECT_EQ(builtin_scene("film-stretch").material->name, "plastic-film");
  EXPECT_EQ(builtin_scene("cloth-shake").material->name, "cotton");
  EXPECT_EQ(builtin_scene("cotton-drape").material->name, "cotton");
}

}  // namespace
}  // namespace clothsim
