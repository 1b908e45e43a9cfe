// The "colliders" list and the collision.* keys of scene files
// (scene/colliders_json.h): every shape read with its fields, paths and
// friction, OBJ meshes read relative to the scene file, errors naming the file,
// the field and the allowed range (or the mesh file and its line), and the
// round trip through scene_to_json().
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "scene/builtin_scenes.h"
#include "scene/colliders_json.h"
#include "scene/scene_model.h"
#include "scene/validate_scene.h"
#include "test_helpers.h"

namespace clothsim {
namespace {

using testing::expect_input_error;
using testing::expect_same_scene;

// A folder of its own under the test scratch directory, holding `files` (name
// -> text).
std::string write_files(const std::string& folder, std::initializer_list<std::pair<std::string, std::string>> files) {
  const std::string directory = std::string(CLOTHSIM_TEST_TMPDIR) + "/" + folder;
  std::filesystem::create_directories(directory);
  for (const auto& [name, text] : files) {
    std::FILE* file = std::fopen((directory + "/" + name).c_str(), "wb");
    EXPECT_NE(file, nullptr);
    std::fwrite(text.data(), 1, text.size(), file);
    std::fclose(file);
  }
  return directory;
}

// A unit square (two triangles as one quad, fanned), with comments, normals and
// a/b/c corners.
constexpr const char* kSquareObj =
    R"(# a unit square in the x-z plane, facing +y
o square
v 0 0 0
v 0 0 1
v 1 0 1
v 1 0 0
vn 0 1 0
f 1//1 2//1 3//1 4//1
)";

TEST(Colliders, ReadsEveryShapeWithFrictionAndPath) {
  const SceneSpec spec = parse_scene(R"({
    "colliders": [
      {"type": "plane", "point": [0, -1, 0], "normal": [0, 2, 0]},
      {"type": "sphere", "center": [0, -0.4, 0], "radius": 0.3, "friction": 0.5},
      {"type": "box", "center": [1, 2, 3], "half_extents": [0.1, 0.2, 0.3]},
      {"type": "capsule", "a": [-1, 0, 0], "b": [1, 0, 0], "radius": 0.05,
       "path": {"type": "sinusoid", "amplitude": [0, 0.1, 0], "frequency": 2}}
    ],
    "collision": {"thickness": 0.01, "self": false, "friction": 0.4}
  })",
                                     "scene.json");
  ASSERT_EQ(spec.colliders.size(), 4u);
  const Collider& plane = spec.colliders[0].collider;
  EXPECT_EQ(plane.shape, ColliderShape::plane);
  EXPECT_EQ(plane.point.y, -1.0);
  EXPECT_EQ(plane.normal.y, 1.0);  // normalised
  EXPECT_LT(plane.friction, 0.0);  // the scene's collision.friction
  const Collider& sphere = spec.colliders[1].collider;
  EXPECT_EQ(sphere.shape, ColliderShape::sphere);
  EXPECT_EQ(sphere.radius, 0.3);
  EXPECT_EQ(sphere.friction, 0.5);
  EXPECT_EQ(spec.colliders[2].collider.half_extents.z, 0.3);
  const Collider& capsule = spec.colliders[3].collider;
  EXPECT_EQ(capsule.shape, ColliderShape::capsule);
  EXPECT_EQ(capsule.path.kind, AnchorPathKind::sinusoid);
  EXPECT_EQ(capsule.path.frequency, 2.0);
  EXPECT_EQ(spec.collision.thickness, 0.01);
  EXPECT_FALSE(spec.collision.self);
  EXPECT_EQ(spec.collision.friction, 0.4);

  const ClothModel model = build_model(spec);
  ASSERT_EQ(model.colliders.size(), 4u);
  EXPECT_EQ(model.colliders[1].radius, 0.3);
  EXPECT_EQ(model.collision.thickness, 0.01);
  EXPECT_NEAR(signed_distance(model.colliders[1], {0.0, 0.0, 0.0}, 0.0).distance, 0.1, 1e-12);

  expect_same_scene(parse_scene(scene_to_json(spec).dump(), "again.json"), spec);
}

TEST(Colliders, MeshIsReadRelativeToTheSceneFileAndRoundTrips) {
  const std::string directory =
      write_files("colliders-mesh", {
                                        {"square.obj", kSquareObj},
                                        {"scene.json",
                                         R"({"colliders": [{"type": "mesh", "file": "square.obj", "scale": 2,
                                        "translate": [0, -0.5, 0], "friction": 0.2}]})"},
                                    });
  const SceneSpec spec = load_scene_file(directory + "/scene.json");
  ASSERT_EQ(spec.colliders.size(), 1u);
  const ColliderSpec& mesh = spec.colliders[0];
  EXPECT_EQ(mesh.mesh_file, "square.obj");
  EXPECT_EQ(mesh.mesh_scale, 2.0);
  ASSERT_NE(mesh.collider.mesh, nullptr);
  EXPECT_EQ(mesh.collider.mesh->vertex.size(), 4u);
  EXPECT_EQ(mesh.collider.mesh->triangle.size(), 2u);  // the quad, fanned
  EXPECT_EQ(mesh.collider.mesh->vertex[2].x, 2.0);     // scaled
  EXPECT_EQ(mesh.collider.mesh->vertex[2].y, -0.5);    // translated
  // Above the square's front, 0.25 m.
  EXPECT_NEAR(signed_distance(mesh.collider, {1.0, -0.25, 1.0}, 0.0).distance, 0.25, 1e-12);

  // Written back as given (not in world coordinates), and read again from the
  // same folder.
  const nlohmann::json written = scene_to_json(spec);
  EXPECT_EQ(written["colliders"][0]["file"], "square.obj");
  EXPECT_EQ(written["colliders"][0]["scale"], 2.0);
  write_files("colliders-mesh", {{"again.json", written.dump()}});
  expect_same_scene(load_scene_file(directory + "/again.json"), spec);
}

// Corners as a/b/c and negative (relative) indices; a pentagon fanned into 3 triangles; CRLF line
// ends and trailing comments.
TEST(Colliders, ObjFaceFormsAndFans) {
  const std::string directory =
      write_files("colliders-obj-forms", {{"forms.obj",
                                           "v 0 0 0\r\nv 1 0 0\r\nv 1 0 1 # w omitted\r\nv 0.5 0 1.5\r\nv 0 0 1\r\n"
                                           "vt 0 0\r\nf 1/1/1 2/1/1 3/1/1 -2/1/1 -1/1/1\r\n"}});
  const auto mesh = scene_json::read_obj_mesh(directory + "/forms.obj", 1.0, {}, "test", "file");
  ASSERT_EQ(mesh->triangle.size(), 3u);
  EXPECT_EQ(mesh->triangle[0], (std::array<std::uint32_t, 3>{0, 1, 2}));
  EXPECT_EQ(mesh->triangle[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
  EXPECT_EQ(mesh->triangle[2], (std::array<std::uint32_t, 3>{0, 3, 4}));
  EXPECT_EQ(mesh->vertex[3].z, 1.5);
}

TEST(Colliders, MeshFileErrorsNameTheFileAndLine) {
  const std::string directory =
      write_files("colliders-bad-mesh", {
                                            {"bad.obj", "v 0 0 0\nv 1 0 0\nv 0 x 1\nf 1 2 3\n"},
                                            {"range.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 4\n"},
                                            {"empty.obj", "v 0 0 0\n"},
                                            {"far.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nv 0 0 2e5\nf 1 2 3\n"},
                                            {"missing.json",
                                             R"({"colliders": [{"type": "sphere", "center": [0, 0, 0], "radius": 1},
                                         {"type": "mesh", "file": "nowhere.obj"}]})"},
                                            {"bad.json", R"({"colliders": [{"type": "mesh", "file": "bad.obj"}]})"},
                                            {"range.json", R"({"colliders": [{"type": "mesh", "file": "range.obj"}]})"},
                                            {"empty.json", R"({"colliders": [{"type": "mesh", "file": "empty.obj"}]})"},
                                            {"far.json", R"({"colliders": [{"type": "mesh", "file": "far.obj",
                                                                            "scale": 10}]})"},
                                        });
  expect_input_error([&] { load_scene_file(directory + "/missing.json"); },
                     {"missing.json", "colliders[1].file", "nowhere.obj"});
  expect_input_error([&] { load_scene_file(directory + "/bad.json"); },
                     {"bad.json", "colliders[0].file", "bad.obj' line 3", "expected a number, got \"x\""});
  expect_input_error([&] { load_scene_file(directory + "/range.json"); },
                     {"range.obj' line 4", "vertex index 4 is outside [1, 3]"});
  expect_input_error([&] { load_scene_file(directory + "/empty.json"); }, {"empty.obj", "no faces"});
  // Scaled, the fourth vertex is 2e6 m away: outside [-1e6, 1e6], where every collider must be.
  expect_input_error([&] { load_scene_file(directory + "/far.json"); },
                     {"far.obj' line 4", "must lie in [-1e6, 1e6] m", "got 2e6"});
}

TEST(Colliders, ErrorsNameTheFieldAndTheAllowedRange) {
  const auto parse = [](const std::string& text) { return parse_scene(text, "scene.json"); };
  expect_input_error(
      [&] { parse(R"({"colliders": [{}, {}, {"type": "sphere", "center": [0, 0, 0], "radius": -1}]})"); },
      {"scene.json", "colliders[0].type", "is required"});
  expect_input_error(
      [&] {
        parse(
            R"({"colliders": [{"type": "box", "center": [0, 0, 0], "half_extents": [1, 1, 1]},
                                {"type": "box", "center": [0, 0, 0], "half_extents": [1, 1, 1]},
                                {"type": "sphere", "center": [0, 0, 0], "radius": -1}]})");
      },
      {"scene.json", "colliders[2].radius", "(0, 1e6]", "-1"});
  expect_input_error([&] { parse(R"({"colliders": [{"type": "plane", "normal": [0, 0, 0]}]})"); },
                     {"colliders[0].normal", "non-zero"});
  expect_input_error([&] { parse(R"({"colliders": [{"type": "cone"}]})"); },
                     {"colliders[0].type", "plane, sphere, box, capsule, mesh", "\"cone\""});
  expect_input_error([&] { parse(R"({"colliders": [{"type": "box", "center": [0, 0, 0], "radius": 1}]})"); },
                     {"colliders[0].radius", "not a key of a box collider"});
  expect_input_error([&] { parse(R"({"colliders": [{"type": "sphere", "center": [0, 0, 0]}]})"); },
                     {"colliders[0].radius", "is required"});
  expect_input_error(
      [&] { parse(R"({"colliders": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "friction": -0.1}]})"); },
      {"colliders[0].friction", "[0, 10]"});
  expect_input_error(
      [&] {
        parse(
            R"({"colliders": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                                 "path": {"type": "linear", "frequency": 1}}]})");
      },
      {"colliders[0].path.frequency", "belongs to a sinusoid path"});
  expect_input_error([&] { parse(R"({"collision": {"thickness": 0}})"); }, {"collision.thickness", "(0, 1]"});
  expect_input_error([&] { parse(R"({"collision": {"friction": 11}})"); }, {"collision.friction", "[0, 10]"});
  expect_input_error([&] { parse(R"({"colliders": {"type": "plane"}})"); }, {"'colliders'", "must be a list"});
}

TEST(Colliders, SetFromTheCommandLineAndValidatedInCode) {
  SceneSpec spec;
  set_scene_field(spec, "colliders", R"([{"type": "sphere", "center": [0, -1, 0], "radius": 0.5}])", "--set");
  set_scene_field(spec, "collision.self", "true", "--set");
  set_scene_field(spec, "collision.thickness", "0.002", "--set");
  ASSERT_EQ(spec.colliders.size(), 1u);
  EXPECT_TRUE(spec.collision.self);
  EXPECT_EQ(spec.collision.thickness, 0.002);
  validate_scene(spec, "code");
  // With self-collision the thickness must leave the lattice's own neighbours apart at rest.
  spec.lattice.spacing = 0.003;
  expect_input_error([&] { validate_scene(spec, "code"); },
                     {"code", "collision.thickness", "half the lattice spacing", "0.0015"});
  set_scene_field(spec, "collision.self", "false", "--set");
  validate_scene(spec, "code");
  spec.lattice.spacing = 1.0;
  spec.colliders[0].collider.radius = 0.0;
  expect_input_error([&] { validate_scene(spec, "code"); }, {"code", "colliders[0].radius", "(0, 1e6]"});
  spec.colliders[0].collider.shape = ColliderShape::plane;
  spec.colliders[0].collider.normal = {0.0, 2.0, 0.0};
  expect_input_error([&] { validate_scene(spec, "code"); }, {"colliders[0].normal", "unit vector"});
  spec.colliders[0].collider.shape = ColliderShape::mesh;
  expect_input_error([&] { validate_scene(spec, "code"); }, {"colliders[0].file", "mesh"});
}

TEST(Colliders, BuiltinColliderScenesLoadAndValidate) {
  for (const char* name : {"drape-sphere", "tablecloth", "pile"}) {
    SCOPED_TRACE(name);
    const SceneSpec spec = builtin_scene(name);
    validate_scene(spec, name);
    EXPECT_FALSE(spec.description.empty());
    ASSERT_GE(spec.colliders.size(), 2u);
    const ClothModel model = build_model(spec);
    EXPECT_EQ(model.colliders.size(), spec.colliders.size());
    // The sheet starts above every obstacle, clear of the thickness.
    const ClothState state = build_initial_state(model, spec);
    for (const Collider& collider : model.colliders) {
      for (const Vec3& x : state.position) {
        ASSERT_GT(signed_distance(collider, x, 0.0).distance, model.collision.thickness);
      }
    }
  }
  EXPECT_EQ(builtin_scene("drape-sphere").colliders[0].collider.shape, ColliderShape::sphere);
  EXPECT_EQ(builtin_scene("tablecloth").colliders[0].collider.shape, ColliderShape::box);
  EXPECT_EQ(builtin_scene("pile").colliders[0].collider.shape, ColliderShape::capsule);
}

}  // namespace
}  // namespace clothsim
