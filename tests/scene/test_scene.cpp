// Scene files: parsing, the paper's argument vector, round trips, error messages, --set, and the
// model and state built from a scene. Small scenes are inline JSON strings (MuJoCo style).
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene/scene_model.h"
#include "scene/validate_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "test_helpers.h"
#include "test_support.h"

namespace clothsim {
namespace {

using testing::expect_input_error;
using testing::expect_same_scene;

SceneSpec parse(const std::string& text) { return parse_scene(text, "scene.json"); }

// ---------------------------------------------------------------------------------------------
// Valid scenes.

TEST(ParseScene, EmptyObjectGivesDefaults) {
  const SceneSpec spec = parse("{}");
  expect_same_scene(spec, SceneSpec{});
  EXPECT_TRUE(spec.anchors.empty());  // a lattice+springs scene has no anchors unless it says so
}

TEST(ParseScene, ReadsEveryFieldOfTheFormat) {
  const SceneSpec spec = parse(R"({
    "name": "all-fields",
    "description": "every key once",
    "lattice": {"rows": 5, "cols": 7, "spacing": 0.5, "particle_mass": 0.2},
    "springs": {
      "connector": {"stiffness": 81, "damping": 6},
      "adjacent": {"stiffness": 3, "damping": 0.5, "rest_angle_deg": 45},
      "opposite": {"stiffness": 1300, "damping": 150, "rest_angle_deg": 180}
    },
    "environment": {"gravity": [0, -1.62, 0], "air_drag": 0.25},
    "anchors": [{"row": 0, "col": 6, "origin": [1, 2, 3], "path": {"type": "linear", "velocity": [0, 0.5, 0]}}],
    "initial": {"velocity": [1, 0, 0], "angular_velocity": [0, 2, 0], "position_noise": 0.01,
                "velocity_noise": 0.02, "seed": 99},
    "integrator": {"method": "rk4", "relative_tolerance": 1e-8, "absolute_tolerance": 1e-7, "time_step": 2e-4,
                   "min_step": 1e-12, "max_step": 0.05, "safety": 0.8, "max_growth": 4, "max_shrink": 0.2},
    "output": {"duration": 3.5, "fps": 30, "until_rest": true, "rest_kinetic_energy": 1e-4},
    "threads": 4
  })");
  EXPECT_EQ(spec.name, "all-fields");
  EXPECT_EQ(spec.description, "every key once");
  EXPECT_EQ(spec.lattice.rows, 5);
  EXPECT_EQ(spec.lattice.cols, 7);
  EXPECT_EQ(spec.lattice.spacing, 0.5);
  EXPECT_EQ(spec.lattice.particle_mass, 0.2);
  EXPECT_EQ(spec.lattice.connector.stiffness, 81.0);
  EXPECT_EQ(spec.lattice.connector.damping, 6.0);
  EXPECT_EQ(spec.lattice.adjacent.stiffness, 3.0);
  EXPECT_EQ(spec.lattice.adjacent.damping, 0.5);
  EXPECT_EQ(spec.lattice.adjacent_rest_angle, std::numbers::pi / 4.0);  // degrees in the file, radians here
  EXPECT_EQ(spec.lattice.opposite.stiffness, 1300.0);
  EXPECT_EQ(spec.lattice.opposite.damping, 150.0);
  EXPECT_EQ(spec.lattice.opposite_rest_angle, std::numbers::pi);
  EXPECT_EQ(spec.environment.gravity, (Vec3{0.0, -1.62, 0.0}));
  EXPECT_EQ(spec.environment.air_drag, 0.25);
  ASSERT_EQ(spec.anchors.size(), 1u);
  EXPECT_EQ(spec.anchors[0].row, 0);
  EXPECT_EQ(spec.anchors[0].col, 6);
  EXPECT_TRUE(spec.anchors[0].origin_given);
  EXPECT_EQ(spec.anchors[0].path.origin, (Vec3{1.0, 2.0, 3.0}));
  EXPECT_EQ(spec.anchors[0].path.kind, AnchorPathKind::linear);
  EXPECT_EQ(spec.anchors[0].path.velocity, (Vec3{0.0, 0.5, 0.0}));
  EXPECT_EQ(spec.initial.velocity, (Vec3{1.0, 0.0, 0.0}));
  EXPECT_EQ(spec.initial.angular_velocity, (Vec3{0.0, 2.0, 0.0}));
  EXPECT_EQ(spec.initial.position_noise, 0.01);
  EXPECT_EQ(spec.initial.velocity_noise, 0.02);
  EXPECT_EQ(spec.initial.seed, 99u);
  EXPECT_EQ(spec.integrator.kind, IntegratorKind::rk4);
  EXPECT_EQ(spec.integrator.relative_tolerance, 1e-8);
  EXPECT_EQ(spec.integrator.absolute_tolerance, 1e-7);
  EXPECT_EQ(spec.integrator.time_step, 2e-4);
  EXPECT_EQ(spec.integrator.min_step, 1e-12);
  EXPECT_EQ(spec.integrator.max_step, 0.05);
  EXPECT_EQ(spec.integrator.safety, 0.8);
  EXPECT_EQ(spec.integrator.max_growth, 4.0);
  EXPECT_EQ(spec.integrator.max_shrink, 0.2);
  EXPECT_EQ(spec.output.duration, 3.5);
  EXPECT_EQ(spec.output.fps, 30);
  EXPECT_TRUE(spec.output.until_rest);
  EXPECT_EQ(spec.output.rest_kinetic_energy, 1e-4);
  EXPECT_EQ(spec.threads, 4);
}

TEST(ParseScene, AcceptsCommentsAndWholeNumbersWrittenAsReals) {
  const SceneSpec spec = parse(R"({
    // scene files are written by hand
    "lattice": {"rows": 3.0, /* a whole number */ "cols": 4}
  })");
  EXPECT_EQ(spec.lattice.rows, 3);
  EXPECT_EQ(spec.lattice.cols, 4);
}

TEST(ParseScene, AnchorPresets) {
  const auto anchors_of = [](const std::string& preset, int rows, int cols) {
    return parse(R"({"lattice": {"rows": )" + std::to_string(rows) + R"(, "cols": )" + std::to_string(cols) +
                 R"(}, "anchors": ")" + preset + R"("})")
        .anchors;
  };
  const std::vector<AnchorSpec> center = anchors_of("center", 4, 5);
  ASSERT_EQ(center.size(), 1u);
  EXPECT_EQ(center[0].row, 2);  // rows/2, integer division
  EXPECT_EQ(center[0].col, 2);
  EXPECT_FALSE(center[0].origin_given);
  EXPECT_EQ(anchors_of("corners", 4, 5).size(), 4u);
  EXPECT_EQ(anchors_of("corners", 1, 5).size(), 2u);  // a 1-wide lattice has 2 distinct corners
  EXPECT_EQ(anchors_of("corners", 1, 2).size(), 2u);
  const std::vector<AnchorSpec> edge = anchors_of("edge-corners", 4, 5);
  ASSERT_EQ(edge.size(), 2u);
  EXPECT_EQ(edge[0].row, 0);
  EXPECT_EQ(edge[0].col, 0);
  EXPECT_EQ(edge[1].row, 0);
  EXPECT_EQ(edge[1].col, 4);
  EXPECT_EQ(anchors_of("edge-corners", 4, 1).size(), 1u);
  EXPECT_TRUE(anchors_of("none", 4, 5).empty());
}

TEST(ParseScene, SinusoidPath) {
  const SceneSpec spec = parse(R"({"anchors": [{"row": 1, "col": 2, "path": {"type": "sinusoid",
      "amplitude": [0, 0.5, 0], "frequency": 2, "phase": 0.25}}]})");
  ASSERT_EQ(spec.anchors.size(), 1u);
  const AnchorPath& path = spec.anchors[0].path;
  EXPECT_EQ(path.kind, AnchorPathKind::sinusoid);
  EXPECT_EQ(path.amplitude, (Vec3{0.0, 0.5, 0.0}));
  EXPECT_EQ(path.frequency, 2.0);
  EXPECT_EQ(path.phase, 0.25);
  EXPECT_FALSE(spec.anchors[0].origin_given);
}

// ---------------------------------------------------------------------------------------------
// The paper's argument vector.

// Distinct values in every position, so that a swapped pair shows.
constexpr const char* kDistinctPaperArgs = "7,9,2.5,3,0.5,1300,150,81,6,1.5";

void expect_distinct_paper_fields(const SceneSpec& spec) {
  EXPECT_EQ(spec.lattice.rows, 7);
  EXPECT_EQ(spec.lattice.cols, 9);
  EXPECT_EQ(spec.lattice.particle_mass, 2.5);
  EXPECT_EQ(spec.lattice.adjacent.stiffness, 3.0);
  EXPECT_EQ(spec.lattice.adjacent.damping, 0.5);
  EXPECT_EQ(spec.lattice.opposite.stiffness, 1300.0);
  EXPECT_EQ(spec.lattice.opposite.damping, 150.0);
  EXPECT_EQ(spec.lattice.connector.stiffness, 81.0);
  EXPECT_EQ(spec.lattice.connector.damping, 6.0);
  EXPECT_EQ(spec.lattice.spacing, 1.5);
  // The paper's rest angles are not arguments: 90 and 180 degrees.
  EXPECT_EQ(spec.lattice.adjacent_rest_angle, std::numbers::pi / 2.0);
  EXPECT_EQ(spec.lattice.opposite_rest_angle, std::numbers::pi);
  ASSERT_EQ(spec.anchors.size(), 1u);
  EXPECT_EQ(spec.anchors[0].row, 3);
  EXPECT_EQ(spec.anchors[0].col, 4);
  EXPECT_FALSE(spec.anchors[0].origin_given);
  EXPECT_EQ(spec.anchors[0].path.kind, AnchorPathKind::fixed);
}

TEST(PaperArgs, TextMapsOntoEveryField) {
  expect_distinct_paper_fields(scene_from_paper_args(kDistinctPaperArgs, "--paper"));
  // Spaces and brackets are fine too.
  expect_distinct_paper_fields(scene_from_paper_args("[7, 9, 2.5, 3, 0.5, 1300, 150, 81, 6, 1.5]", "--paper"));
  expect_distinct_paper_fields(scene_from_paper_args("7 9 2.5 3 0.5 1300 150 81 6 1.5", "--paper"));
  const SceneSpec spec = scene_from_paper_args("[21,21, 1,4,1,1400,200,80,5,1]", "--paper");
  EXPECT_EQ(spec.name, "paper-args");
  EXPECT_EQ(spec.description,
            "The paper's argument vector [21, 21, 1, 4, 1, 1400, 200, 80, 5, 1], centre particle anchored.");
}

TEST(PaperArgs, JsonMapsOntoEveryField) {
  const SceneSpec spec = parse(std::string(R"({"paper_args": [)") + kDistinctPaperArgs + "]}");
  expect_distinct_paper_fields(spec);
  // The same lattice as the text form; only name and description differ.
  SceneSpec from_text = scene_from_paper_args(kDistinctPaperArgs, "--paper");
  from_text.name = spec.name;
  from_text.description = spec.description;
  expect_same_scene(spec, from_text);
}

TEST(PaperArgs, ExplicitAnchorsReplaceTheCentre) {
  EXPECT_TRUE(parse(R"({"paper_args": [5,5,1,4,1,1400,200,80,5,1], "anchors": "none"})").anchors.empty());
  const SceneSpec corners = parse(R"({"paper_args": [5,5,1,4,1,1400,200,80,5,1], "anchors": "corners"})");
  EXPECT_EQ(corners.anchors.size(), 4u);
}

TEST(PaperArgs, Errors) {
  expect_input_error([] { scene_from_paper_args("21,21,1,4,1,1400,200,80,5", "--paper"); },
                     {"--paper: field 'paper_args'", "exactly 10 numbers", "got 9"});
  expect_input_error([] { scene_from_paper_args("21,21,-1,4,1,1400,200,80,5,1", "--paper"); },
                     {"--paper: field 'paper_args[2] (mass)': must be a number in (0, 1e6], got \"-1\""});
  expect_input_error([] { scene_from_paper_args("21,21.5,1,4,1,1400,200,80,5,1", "--paper"); },
                     {"paper_args[1] (cols)", "an integer in [1, 4096]"});
  expect_input_error([] { scene_from_paper_args("21,21,1,4,1,1400,200,80,5,zero", "--paper"); },
                     {"paper_args[9] (connector length)", "must be a number", "\"zero\""});
  expect_input_error([] { parse(R"({"paper_args": [21,21,-1,4,1,1400,200,80,5,1]})"); },
                     {"scene.json: field 'paper_args[2] (mass)': must be a number in (0, 1e6], got -1"});
  expect_input_error([] { parse(R"({"paper_args": [21,21,1,4,-1,1400,200,80,5,1]})"); },
                     {"paper_args[4] (c adjacent)", "[0, 1e9]"});
  expect_input_error([] { parse(R"({"paper_args": "21,21,1,4,1,1400,200,80,5,1"})"); },
                     {"paper_args", "array of 10 numbers"});
}

// ---------------------------------------------------------------------------------------------
// Round trip: scene_to_json -> text -> parse_scene.

SceneSpec scene_with_every_path_kind() {
  SceneSpec spec = parse(R"({
    "name": "paths", "description": "three anchor paths",
    "lattice": {"rows": 6, "cols": 4, "spacing": 0.3},
    "springs": {"adjacent": {"rest_angle_deg": 75}, "opposite": {"rest_angle_deg": 170.5}},
    "anchors": [
      {"row": 0, "col": 0},
      {"row": 0, "col": 3, "origin": [0.1, 0.2, 0.3], "path": {"type": "linear", "velocity": [0, 1, 0]}},
      {"row": 5, "col": 1, "path": {"type": "sinusoid", "amplitude": [0.1, 0, 0], "frequency": 3, "phase": 1.5}}
    ],
    "initial": {"seed": 9007199254740992},
    "integrator": {"method": "symplectic-euler"},
    "output": {"until_rest": true},
    "threads": 3
  })");
  return spec;
}

TEST(SceneToJson, RoundTripReproducesTheScene) {
  const SceneSpec original = scene_with_every_path_kind();
  const nlohmann::json written = scene_to_json(original);
  const SceneSpec reread = parse_scene(written.dump(2), "round-trip");
  expect_same_scene(original, reread);
  EXPECT_EQ(scene_to_json(reread), written);
}

TEST(SceneToJson, WritesEveryKey) {
  const nlohmann::json written = scene_to_json(scene_with_every_path_kind());
  for (std::string_view key : all_scene_keys()) {
    if (key == "paper_args") continue;             // written in the lattice + springs form
    std::string pointer = "/" + std::string(key);  // "lattice.rows" -> "/lattice/rows"
    std::replace(pointer.begin(), pointer.end(), '.', '/');
    EXPECT_TRUE(written.contains(nlohmann::json::json_pointer(pointer))) << key;
  }
  EXPECT_FALSE(written.contains("paper_args"));
  EXPECT_EQ(written["anchors"][0]["path"]["type"], "fixed");
  EXPECT_FALSE(written["anchors"][0].contains("origin"));  // defaults to the rest position
  EXPECT_EQ(written["anchors"][1]["origin"], nlohmann::json::array({0.1, 0.2, 0.3}));
  EXPECT_EQ(written["integrator"]["method"], "symplectic-euler");
  EXPECT_EQ(written["springs"]["adjacent"]["rest_angle_deg"], 75.0);
}

// ---------------------------------------------------------------------------------------------
// Malformed scenes: each message names the source, the dotted field and what is allowed.

struct MalformedScene {
  const char* what;
  const char* json;
  std::vector<std::string_view> pieces;
};

// gtest prints the parameter of a failing case with this.
void PrintTo(const MalformedScene& scene, std::ostream* out) { *out << scene.what; }

class MalformedSceneTest : public ::testing::TestWithParam<MalformedScene> {};

TEST_P(MalformedSceneTest, ThrowsInputErrorNamingFieldAndRange) {
  const MalformedScene& scene = GetParam();
  try {
    parse_scene(scene.json, "scene.json");
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_EQ(error.source(), "scene.json");
    EXPECT_TRUE(message.starts_with("scene.json: ")) << message;
    for (std::string_view piece : scene.pieces) {
      EXPECT_NE(message.find(piece), std::string::npos)
          << scene.what << "\nmessage: " << message << "\nmissing: " << piece;
    }
    return;
  }
  ADD_FAILURE() << scene.what << ": no InputError";
}

const MalformedScene kMalformedScenes[] = {
    {"rows 0",
     R"({"lattice": {"rows": 0}})",
     {"scene.json: field 'lattice.rows': must be an integer in [1, 4096], got 0"}},
    {"rows 2.5", R"({"lattice": {"rows": 2.5}})", {"field 'lattice.rows'", "an integer in [1, 4096]", "got 2.5"}},
    {"cols 5000", R"({"lattice": {"cols": 5000}})", {"field 'lattice.cols'", "[1, 4096]", "got 5000"}},
    {"single particle", R"({"lattice": {"rows": 1, "cols": 1}})", {"lattice.rows", "at least 2 particles", "1 x 1"}},
    {"spacing 0", R"({"lattice": {"spacing": 0}})", {"field 'lattice.spacing'", "a number in (0, 1000]", "got 0"}},
    {"negative mass",
     R"({"lattice": {"particle_mass": -1}})",
     {"field 'lattice.particle_mass'", "a number in (0, 1e6]", "got -1"}},
    {"negative stiffness",
     R"({"springs": {"connector": {"stiffness": -80}}})",
     {"field 'springs.connector.stiffness'", "a number in [0, 1e9]", "got -80"}},
    {"rest angle 200",
     R"({"springs": {"adjacent": {"rest_angle_deg": 200}}})",
     {"field 'springs.adjacent.rest_angle_deg'", "[0, 180]", "got 200"}},
    {"typo with suggestion",
     R"({"lattice": {"colums": 5}})",
     {"scene.json: field 'lattice.colums': unknown field (did you mean 'lattice.cols'?)"}},
    {"unknown nested key",
     R"({"springs": {"opposite": {"stifness": 5}}})",
     {"field 'springs.opposite.stifness'", "did you mean 'springs.opposite.stiffness'"}},
    {"unknown key without a close match",
     R"({"output": {"video": true}})",
     {"field 'output.video'", "unknown field",
      "known fields in 'output': duration, fps, until_rest, rest_kinetic_energy, rest_duration"}},
    {"key in the wrong group", R"({"fps": 30})", {"field 'fps'", "did you mean 'output.fps'"}},
    {"unknown top-level key", R"({"lattise": {}})", {"field 'lattise'", "did you mean 'lattice'"}},
    {"dotted key in a file", R"({"lattice.rows": 5})", {"field 'lattice.rows'", "nest objects"}},
    {"string for number",
     R"({"output": {"fps": "sixty"}})",
     {"scene.json: field 'output.fps': must be a number, got string \"sixty\""}},
    {"group not an object", R"({"lattice": 5})", {"field 'lattice'", "must be an object", "got 5"}},
    {"bad method",
     R"({"integrator": {"method": "euler"}})",
     {"scene.json: field 'integrator.method': must be one of rkf45, rk4, symplectic-euler, implicit-euler, imex, got "
      "\"euler\""}},
    {"method not a string", R"({"integrator": {"method": 4}})", {"integrator.method", "rkf45, rk4", "got 4"}},
    {"fps 0", R"({"output": {"fps": 0}})", {"field 'output.fps'", "an integer in [1, 10000]", "got 0"}},
    {"negative duration", R"({"output": {"duration": -5}})", {"field 'output.duration'", "(0, 1e7]", "got -5"}},
    {"non-boolean until_rest",
     R"({"output": {"until_rest": 1}})",
     {"field 'output.until_rest'", "must be a boolean (true or false)", "got 1"}},
    {"string until_rest", R"({"output": {"until_rest": "yes"}})", {"output.until_rest", "boolean", "string \"yes\""}},
    {"rtol 0",
     R"({"integrator": {"relative_tolerance": 0}})",
     {"field 'integrator.relative_tolerance'", "[1e-14, 1]", "got 0"}},
    {"min_step > max_step",
     R"({"integrator": {"min_step": 0.5, "max_step": 0.1, "time_step": 1}})",
     {"field 'integrator.min_step'", "must be <= integrator.max_step (0.1)", "got 0.5"}},
    {"min_step > time_step",
     R"({"integrator": {"min_step": 0.01}})",
     {"field 'integrator.min_step'", "must be <= integrator.time_step (0.001)", "got 0.01"}},
    {"threads 2000", R"({"threads": 2000})", {"field 'threads'", "[0, 1024]"}},
    {"seed above 2^53",
     R"({"initial": {"seed": 9007199254740993}})",
     {"field 'initial.seed'", "[0, 9007199254740992]", "got 9007199254740993"}},
    {"negative seed", R"({"initial": {"seed": -1}})", {"field 'initial.seed'", "an integer in"}},
    {"gravity of 2 numbers",
     R"({"environment": {"gravity": [0, -9.81]}})",
     {"field 'environment.gravity'", "array of 3 numbers"}},
    {"gravity out of range",
     R"({"environment": {"gravity": [0, -2000, 0]}})",
     {"field 'environment.gravity[1]'", "[-1000, 1000]", "got -2000"}},
    {"angular velocity component a string",
     R"({"initial": {"angular_velocity": [0, "1", 0]}})",
     {"field 'initial.angular_velocity[1]'", "must be a number"}},
    {"name not a string", R"({"name": 5})", {"field 'name'", "must be a string"}},
    {"anchor row out of range",
     R"({"lattice": {"rows": 5, "cols": 5}, "anchors": [{"row": 5, "col": 0}]})",
     {"field 'anchors[0].row'", "an integer in [0, 4]", "got 5"}},
    {"anchor col negative", R"({"anchors": [{"row": 0, "col": -1}]})", {"field 'anchors[0].col'", "[0, 20]"}},
    {"anchor twice",
     R"({"anchors": [{"row": 1, "col": 1}, {"row": 0, "col": 0}, {"row": 1, "col": 1}]})",
     {"field 'anchors[2]'", "(row 1, col 1) is anchored twice", "anchors[0]"}},
    {"anchor key typo",
     R"({"anchors": [{"row": 1, "colum": 1}]})",
     {"field 'anchors[0].colum'", "did you mean 'anchors[0].col'"}},
    {"anchor not an object", R"({"anchors": [[1, 1]]})", {"field 'anchors[0]'", "must be an object"}},
    {"unknown preset",
     R"({"anchors": "middle"})",
     {"field 'anchors'", "one of center, corners, edge-corners, none or a list of anchors", "got \"middle\""}},
    {"sinusoid key on a fixed path",
     R"({"anchors": [{"path": {"type": "fixed", "amplitude": [0, 1, 0]}}]})",
     {"field 'anchors[0].path.amplitude'", "belongs to a sinusoid path, not a fixed one",
      "keys of a fixed path: type"}},
    {"velocity on a sinusoid path",
     R"({"anchors": [{"path": {"type": "sinusoid", "velocity": [0, 1, 0]}}]})",
     {"field 'anchors[0].path.velocity'", "belongs to a linear path"}},
    {"unknown path type",
     R"({"anchors": [{"path": {"type": "circle"}}]})",
     {"field 'anchors[0].path.type'", "one of fixed, linear, sinusoid", "got \"circle\""}},
    {"frequency out of range",
     R"({"anchors": [{"path": {"type": "sinusoid", "frequency": 20000}}]})",
     {"field 'anchors[0].path.frequency'", "[0, 10000]", "got 20000"}},
    {"origin out of range",
     R"({"anchors": [{"origin": [0, 2e6, 0]}]})",
     {"field 'anchors[0].origin[1]'", "[-1e6, 1e6]"}},
    {"paper_args with 9 numbers",
     R"({"paper_args": [21, 21, 1, 4, 1, 1400, 200, 80, 5]})",
     {"field 'paper_args'", "exactly 10 numbers (rows, cols, mass, k adjacent", "got 9"}},
    {"paper_args plus lattice",
     R"({"paper_args": [21, 21, 1, 4, 1, 1400, 200, 80, 5, 1], "lattice": {"rows": 3}})",
     {"field 'paper_args'", "cannot be combined with 'lattice' or 'springs'"}},
    {"paper_args rows 0",
     R"({"paper_args": [0, 21, 1, 4, 1, 1400, 200, 80, 5, 1]})",
     {"field 'paper_args[0] (rows)'", "[1, 4096]"}},
    {"duplicate key", R"({"lattice": {"rows": 3, "rows": 4}})", {"field 'lattice.rows'", "appears twice"}},
    {"duplicate key in an anchor",
     R"({"anchors": [{"row": 0}, {"col": 1, "col": 2}]})",
     {"field 'anchors[1].col'", "appears twice"}},
    {"syntax error", "{\n  \"name\": \"x\",\n  oops\n}", {"scene.json: line 3, column 3: JSON syntax error: "}},
    {"syntax error at the end", "{\"lattice\": {\"rows\": 3}", {"scene.json: line 1, column", "JSON syntax error"}},
    {"top-level array", "[1, 2, 3]", {"scene.json: the top level must be a JSON object", "got array"}},
    {"empty text", "", {"scene.json: line 1, column", "JSON syntax error"}},
};

INSTANTIATE_TEST_SUITE_P(Scenes, MalformedSceneTest, ::testing::ValuesIn(kMalformedScenes),
                         [](const ::testing::TestParamInfo<MalformedScene>& case_info) {
                           return testing::case_name(case_info.param.what);
                         });

TEST(LoadSceneFile, MissingFile) {
  const std::string path = CLOTHSIM_SOURCE_DIR "/tests/scene/no-such-scene.json";
  expect_input_error([&] { load_scene_file(path); }, {path + ": cannot read file: No such file or directory"});
}

TEST(LoadSceneFile, DirectoryIsNotAFile) {
  expect_input_error([] { load_scene_file(CLOTHSIM_SOURCE_DIR "/tests/scene"); }, {"cannot read file: "});
}

TEST(LoadScene, UnknownNameMentionsTheBuiltins) {
  expect_input_error([] { load_scene("paper-fig7"); },
                     {"paper-fig7: cannot read file: No such file or directory", "not a built-in scene", "paper-fig4"});
}

TEST(LoadSceneFile, ReadsAFileAndNamesItInErrors) {
  const std::string directory = CLOTHSIM_TEST_TMPDIR;
  std::filesystem::create_directories(directory);
  const std::string path = directory + "/scene-test.json";
  {
    std::FILE* file = std::fopen(path.c_str(), "wb");
    ASSERT_NE(file, nullptr);
    const std::string text = R"({"name": "from-file", "lattice": {"rows": 3, "cols": 3}, "anchors": "center"})";
    std::fwrite(text.data(), 1, text.size(), file);
    std::fclose(file);
  }
  const SceneSpec spec = load_scene(path);
  EXPECT_EQ(spec.name, "from-file");
  EXPECT_EQ(spec.anchors.size(), 1u);
  {
    std::FILE* file = std::fopen(path.c_str(), "wb");
    ASSERT_NE(file, nullptr);
    const std::string text = "{\"lattice\": {\"rows\": -3}}";
    std::fwrite(text.data(), 1, text.size(), file);
    std::fclose(file);
  }
  expect_input_error([&] { load_scene(path); }, {path + ": field 'lattice.rows': must be an integer in [1, 4096]"});
  std::filesystem::remove(path);
}

// ---------------------------------------------------------------------------------------------
// set_scene_field: the CLI's --set key=value.

TEST(SetSceneField, Scalars) {
  SceneSpec spec;
  set_scene_field(spec, "lattice.rows", "11", "--set");
  set_scene_field(spec, "output.fps", " 30 ", "--fps");
  set_scene_field(spec, "output.until_rest", "true", "--set");
  set_scene_field(spec, "springs.adjacent.rest_angle_deg", "45", "--set");
  set_scene_field(spec, "integrator.time_step", "2.5e-4", "--set");
  set_scene_field(spec, "initial.seed", "123456789", "--set");
  set_scene_field(spec, "threads", "+8", "--threads");
  EXPECT_EQ(spec.lattice.rows, 11);
  EXPECT_EQ(spec.output.fps, 30);
  EXPECT_TRUE(spec.output.until_rest);
  EXPECT_EQ(spec.lattice.adjacent_rest_angle, std::numbers::pi / 4.0);
  EXPECT_EQ(spec.integrator.time_step, 2.5e-4);
  EXPECT_EQ(spec.initial.seed, 123456789u);
  EXPECT_EQ(spec.threads, 8);
  set_scene_field(spec, "output.until_rest", "false", "--set");
  EXPECT_FALSE(spec.output.until_rest);
}

TEST(SetSceneField, EveryRegistryParameterReadsBackWhatWasSet) {
  for (const ScalarParameter& parameter : scalar_parameters()) {
    SceneSpec spec;
    // An allowed value that differs from most defaults: the upper end, or the lower if open.
    const double value =
        parameter.range.max_inclusive ? parameter.range.max : 0.5 * (parameter.range.min + parameter.range.max);
    const std::string text = parameter.type == ParameterType::boolean ? "true" : format_number(value);
    set_scene_field(spec, parameter.key, text, "--set");
    EXPECT_EQ(parameter.get(spec), value) << parameter.key;
  }
}

TEST(SetSceneField, VectorsMethodAnchorsAndText) {
  SceneSpec spec;
  set_scene_field(spec, "environment.gravity", "0,-1.62,0", "--set");
  set_scene_field(spec, "initial.angular_velocity", "[0, 1, 0.5]", "--set");
  set_scene_field(spec, "integrator.method", "rk4", "--method");
  set_scene_field(spec, "name", "moon", "--set");
  EXPECT_EQ(spec.environment.gravity, (Vec3{0.0, -1.62, 0.0}));
  EXPECT_EQ(spec.initial.angular_velocity, (Vec3{0.0, 1.0, 0.5}));
  EXPECT_EQ(spec.integrator.kind, IntegratorKind::rk4);
  EXPECT_EQ(spec.name, "moon");

  set_scene_field(spec, "anchors", "corners", "--anchors");
  ASSERT_EQ(spec.anchors.size(), 4u);
  EXPECT_EQ(spec.anchors[3].row, 20);
  EXPECT_EQ(spec.anchors[3].col, 20);
  set_scene_field(spec, "anchors", R"([{"row": 2, "col": 3, "path": {"type": "linear", "velocity": [0, 1, 0]}}])",
                  "--anchors");
  ASSERT_EQ(spec.anchors.size(), 1u);
  EXPECT_EQ(spec.anchors[0].path.kind, AnchorPathKind::linear);
  set_scene_field(spec, "anchors", "none", "--anchors");
  EXPECT_TRUE(spec.anchors.empty());

  set_scene_field(spec, "paper_args", "11,11,1,400,10,1400,200,80,5,1", "--paper");
  EXPECT_EQ(spec.lattice.rows, 11);
  EXPECT_EQ(spec.lattice.adjacent.stiffness, 400.0);
  ASSERT_EQ(spec.anchors.size(), 1u);
  EXPECT_EQ(spec.anchors[0].row, 5);
  validate_scene(spec, "--set");
}

TEST(SetSceneField, Errors) {
  SceneSpec spec;
  const auto set = [&](std::string_view key, std::string_view value, const std::string& source) {
    return [&spec, key, value, source] { set_scene_field(spec, key, value, source); };
  };
  expect_input_error(set("output.fps", "sixty", "--fps"),
                     {"--fps: field 'output.fps': must be a number, got \"sixty\""});
  expect_input_error(set("output.fps", "0", "--fps"),
                     {"--fps: field 'output.fps': must be an integer in [1, 10000], got \"0\""});
  expect_input_error(set("lattice.rows", "2.5", "--set lattice.rows=2.5"),
                     {"--set lattice.rows=2.5: field 'lattice.rows'", "an integer in [1, 4096]", "\"2.5\""});
  expect_input_error(set("lattice.spacing", "nan", "--set"), {"field 'lattice.spacing'", "(0, 1000]", "\"nan\""});
  expect_input_error(set("lattice.spacing", "inf", "--set"), {"field 'lattice.spacing'", "(0, 1000]", "\"inf\""});
  expect_input_error(set("output.duration", "1e400", "--duration"), {"field 'output.duration'", "(0, 1e7]"});
  expect_input_error(set("output.duration", "", "--duration"), {"field 'output.duration'", "must be a number"});
  expect_input_error(set("output.duration", "5s", "--duration"),
                     {"field 'output.duration'", "must be a number, got \"5s\""});
  expect_input_error(set("output.until_rest", "yes", "--set"),
                     {"field 'output.until_rest'", "a boolean (true or false)"});
  expect_input_error(set("environment.gravity", "0,-9.81", "--gravity"),
                     {"--gravity: field 'environment.gravity'", "3 numbers x,y,z"});
  expect_input_error(set("environment.gravity", "0,-9.81,nan", "--gravity"),
                     {"field 'environment.gravity[2]'", "[-1000, 1000]"});
  // Names and descriptions go into scene.json and summary.json: UTF-8, as in a scene file.
  expect_input_error(set("name", "caf\xC3", "--set"), {"--set: field 'name': must be UTF-8 text", "at byte 3"});
  expect_input_error(set("description", "\xED\xA0\x80", "--set"), {"field 'description': must be UTF-8 text"});
  expect_input_error(set("material", "\x93paper", "--material"), {"--material: field 'material': must be UTF-8 text"});
  EXPECT_NO_THROW(set_scene_field(spec, "name", "caf\xC3\xA9 \xF0\x9F\xA7\xB5", "--set"));
  EXPECT_EQ(spec.name, "caf\xC3\xA9 \xF0\x9F\xA7\xB5");
  expect_input_error(set("integrator.method", "euler", "--method"),
                     {"--method: field 'integrator.method': must be one of rkf45, rk4, symplectic-euler, "
                      "implicit-euler, imex, got \"euler\""});
  expect_input_error(set("anchors", "middle", "--anchors"),
                     {"--anchors: field 'anchors'", "center, corners, edge-corners, none"});
  expect_input_error(set("anchors", "[{\"row\": 99}]", "--anchors"), {"--anchors: field 'anchors[0].row'", "[0, 20]"});
  expect_input_error(set("anchors", "[{\"row\": ", "--anchors"), {"--anchors: line 1, column", "JSON syntax error"});
  expect_input_error(set("output.fsp", "30", "--set output.fsp=30"),
                     {"--set output.fsp=30: field 'output.fsp': unknown field (did you mean 'output.fps'?)"});
  expect_input_error(set("fps", "30", "--set"), {"field 'fps'", "did you mean 'output.fps'"});
  expect_input_error(set("springs.opposite", "3", "--set"),
                     {"field 'springs.opposite'", "group of fields", "springs.opposite.stiffness"});
  expect_input_error(set("paper_args", "1,2,3", "--paper"), {"--paper: field 'paper_args'", "got 3"});
}

TEST(SetSceneField, LeavesCrossFieldChecksToValidateScene) {
  SceneSpec spec;
  set_scene_field(spec, "anchors", "corners", "--set");  // (20, 20) on the 21 x 21 default
  set_scene_field(spec, "lattice.rows", "5", "--set");   // allowed alone
  expect_input_error([&] { validate_scene(spec, "--set"); }, {"--set: field 'anchors[2].row'", "[0, 4]", "got 20"});
}

// ---------------------------------------------------------------------------------------------
// validate_scene on scenes built in code.

TEST(ValidateScene, ChecksScenesBuiltInCode) {
  SceneSpec spec;
  spec.lattice.spacing = std::nan("");
  expect_input_error([&] { validate_scene(spec, "api"); }, {"api: field 'lattice.spacing'", "(0, 1000]", "nan"});
  spec = SceneSpec{};
  spec.lattice.adjacent_rest_angle = 4.0;  // radians: about 229 degrees
  expect_input_error([&] { validate_scene(spec, "api"); }, {"field 'springs.adjacent.rest_angle_deg'", "[0, 180]"});
  spec = SceneSpec{};
  spec.anchors.push_back(AnchorSpec{0, 0, AnchorPath{}, false});
  spec.anchors[0].path.frequency = -1.0;
  expect_input_error([&] { validate_scene(spec, "api"); }, {"field 'anchors[0].path.frequency'", "[0, 10000]"});
  spec = SceneSpec{};
  spec.environment.gravity.z = std::numeric_limits<double>::infinity();
  expect_input_error([&] { validate_scene(spec, "api"); }, {"field 'environment.gravity[2]'"});
  EXPECT_NO_THROW(validate_scene(SceneSpec{}, "api"));
}

// ---------------------------------------------------------------------------------------------
// build_model and build_initial_state.

TEST(BuildModel, AnchorsAtRestPositionOrGivenOrigin) {
  const SceneSpec spec = parse(R"({
    "lattice": {"rows": 4, "cols": 3, "spacing": 0.5},
    "anchors": [{"row": 3, "col": 0},
                {"row": 0, "col": 2, "origin": [1, 2, 3], "path": {"type": "linear", "velocity": [0, 1, 0]}}],
    "initial": {"velocity": [0, 0, 2]}
  })");
  const ClothModel model = build_model(spec);
  ASSERT_EQ(model.anchor_count(), 2u);
  EXPECT_EQ(model.anchors[0].particle, 9u);  // row 3 * 3 cols + col 0
  EXPECT_EQ(model.anchors[0].path.origin, model.particle_rest_position[9]);
  EXPECT_EQ(model.anchors[0].path.origin, (Vec3{-0.5, 0.0, 0.75}));
  EXPECT_EQ(model.anchors[1].particle, 2u);
  EXPECT_EQ(model.anchors[1].path.origin, (Vec3{1.0, 2.0, 3.0}));
  EXPECT_TRUE(model.is_anchored(9));
  EXPECT_TRUE(model.is_anchored(2));
  EXPECT_FALSE(model.is_anchored(0));

  const ClothState state = build_initial_state(model, spec);
  EXPECT_EQ(state.position[2], (Vec3{1.0, 2.0, 3.0}));  // anchors follow their path
  EXPECT_EQ(state.velocity[2], (Vec3{0.0, 1.0, 0.0}));
  EXPECT_EQ(state.velocity[9], (Vec3{}));
  EXPECT_EQ(state.velocity[0], (Vec3{0.0, 0.0, 2.0}));  // free particles get the initial velocity
  EXPECT_EQ(state.position[0], model.particle_rest_position[0]);
}

TEST(BuildModel, LatticeRestPositionMatchesTheModel) {
  LatticeDef lattice;
  lattice.rows = 4;
  lattice.cols = 7;
  lattice.spacing = 0.3;
  const ClothModel model = build_lattice(lattice, Environment{}, {});
  for (int row = 0; row < lattice.rows; ++row) {
    for (int col = 0; col < lattice.cols; ++col) {
      EXPECT_EQ(lattice_rest_position(lattice, row, col),
                model.particle_rest_position[lattice_index(lattice.cols, row, col)]);
    }
  }
}

TEST(BuildInitialState, NoiseIsReproducible) {
  const SceneSpec spec = parse(R"({"lattice": {"rows": 3, "cols": 3},
      "initial": {"position_noise": 0.1, "velocity_noise": 0.2, "seed": 5}})");
  const ClothModel model = build_model(spec);
  const ClothState first = build_initial_state(model, spec);
  const ClothState second = build_initial_state(model, spec);
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    EXPECT_EQ(first.position[p], second.position[p]);
    EXPECT_EQ(first.velocity[p], second.velocity[p]);
    EXPECT_LE(std::abs(first.position[p].y), 0.1);
    EXPECT_NE(first.position[p], model.particle_rest_position[p]);
  }
}

}  // namespace
}  // namespace clothsim
