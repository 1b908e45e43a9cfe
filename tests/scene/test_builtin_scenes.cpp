// The built-in scene library: every scene parses, validates, builds the lattice the paper's
// rules predict, and survives a round trip through the file format.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene/scene_model.h"
#include "scene/validate_scene.h"
#include "test_helpers.h"

namespace clothsim {
namespace {

using testing::expect_input_error;
using testing::expect_same_scene;

// Radial springs by the paper's rule: interior particles 4 adjacent + 2 opposite, edge particles
// 2 + 1, corners 1 + 0 (lattices at least 2 x 2).
std::size_t expected_radial_count(int rows, int cols) {
  std::size_t count = 0;
  for (int row = 0; row < rows; ++row) {
    for (int col = 0; col < cols; ++col) {
      const bool row_edge = row == 0 || row == rows - 1;
      const bool col_edge = col == 0 || col == cols - 1;
      if (row_edge && col_edge) {
        count += 1;
      } else if (row_edge || col_edge) {
        count += 3;
      } else {
        count += 6;
      }
    }
  }
  return count;
}

TEST(BuiltinScenes, ListsTheScenes) {
  const std::vector<BuiltinScene> scenes = builtin_scenes();
  std::vector<std::string> names;
  for (const BuiltinScene& scene : scenes) {
    names.push_back(scene.name);
    EXPECT_FALSE(scene.description.empty()) << scene.name;
  }
  EXPECT_EQ(names, (std::vector<std::string>{"paper-fig4", "paper-fig5", "paper-fig6", "drape-corners", "free-spin",
                                             "cotton-drape", "tear-pull", "paper-crease", "film-stretch", "cloth-shake",
                                             "drape-sphere", "tablecloth", "sphere-sweep", "pile", "tear-crumple"}));
  EXPECT_FALSE(is_builtin_scene("paper-fig7"));
  expect_input_error([] { builtin_scene("paper-fig7"); }, {"paper-fig7", "not a built-in scene", "paper-fig4"});
}

TEST(BuiltinScenes, EachParsesValidatesAndBuildsThePaperLattice) {
  for (const BuiltinScene& entry : builtin_scenes()) {
    SCOPED_TRACE(entry.name);
    ASSERT_TRUE(is_builtin_scene(entry.name));
    const SceneSpec spec = builtin_scene(entry.name);
    EXPECT_EQ(spec.name, entry.name);
    EXPECT_EQ(spec.description, entry.description);
    EXPECT_NO_THROW(validate_scene(spec, entry.name));
    expect_same_scene(load_scene(entry.name), spec);

    const int rows = spec.lattice.rows;
    const int cols = spec.lattice.cols;
    const ClothModel model = build_model(spec);
    EXPECT_EQ(model.particle_count(), static_cast<std::size_t>(rows * cols));
    EXPECT_EQ(model.connector_count(), static_cast<std::size_t>(rows * (cols - 1) + cols * (rows - 1)));
    EXPECT_EQ(model.radial_count(), expected_radial_count(rows, cols));
    EXPECT_EQ(model.anchor_count(), spec.anchors.size());

    const ClothState state = build_initial_state(model, spec);
    EXPECT_EQ(state.position.size(), model.particle_count());
    EXPECT_EQ(state.velocity.size(), model.particle_count());
  }
}

TEST(BuiltinScenes, RoundTripThroughTheFileFormat) {
  for (const BuiltinScene& entry : builtin_scenes()) {
    SCOPED_TRACE(entry.name);
    const SceneSpec spec = builtin_scene(entry.name);
    expect_same_scene(parse_scene(scene_to_json(spec).dump(), entry.name + ".json"), spec);
  }
}

TEST(BuiltinScenes, PaperFigure4AnchorsTheCentreAtTheOrigin) {
  const SceneSpec spec = builtin_scene("paper-fig4");
  EXPECT_EQ(spec.lattice.rows, 21);
  EXPECT_EQ(spec.lattice.cols, 21);
  EXPECT_EQ(spec.lattice.particle_mass, 1.0);
  EXPECT_EQ(spec.lattice.adjacent.stiffness, 4.0);
  EXPECT_EQ(spec.lattice.adjacent.damping, 1.0);
  EXPECT_EQ(spec.lattice.opposite.stiffness, 1400.0);
  EXPECT_EQ(spec.lattice.opposite.damping, 200.0);
  EXPECT_EQ(spec.lattice.connector.stiffness, 80.0);
  EXPECT_EQ(spec.lattice.connector.damping, 5.0);
  EXPECT_EQ(spec.lattice.spacing, 1.0);
  EXPECT_NE(spec.description.find("Figure 4"), std::string::npos);
  EXPECT_EQ(spec.output.duration, 20.0);
  EXPECT_EQ(spec.output.fps, 60);

  const ClothModel model = build_model(spec);
  ASSERT_EQ(model.anchor_count(), 1u);
  EXPECT_EQ(model.anchors[0].particle, 220u);
  EXPECT_EQ(model.anchors[0].path.kind, AnchorPathKind::fixed);
  EXPECT_EQ(model.anchors[0].path.position(0.0), (Vec3{0.0, 0.0, 0.0}));
  EXPECT_EQ(model.particle_inverse_mass[220], 0.0);
  for (std::size_t p = 0; p < model.particle_count(); ++p) EXPECT_EQ(model.is_anchored(p), p == 220) << p;
}

TEST(BuiltinScenes, PaperFigures5And6) {
  const SceneSpec fig5 = builtin_scene("paper-fig5");
  const SceneSpec fig6 = builtin_scene("paper-fig6");
  for (const SceneSpec* spec : {&fig5, &fig6}) {
    EXPECT_EQ(spec->lattice.rows, 11);
    EXPECT_EQ(spec->lattice.cols, 11);
    ASSERT_EQ(spec->anchors.size(), 1u);
    EXPECT_EQ(build_model(*spec).anchors[0].particle, 60u);
    EXPECT_EQ(build_model(*spec).anchors[0].path.origin, (Vec3{0.0, 0.0, 0.0}));
  }
  EXPECT_EQ(fig5.lattice.adjacent.stiffness, 4.0);
  EXPECT_EQ(fig5.lattice.adjacent.damping, 1.0);
  EXPECT_EQ(fig6.lattice.adjacent.stiffness, 400.0);
  EXPECT_EQ(fig6.lattice.adjacent.damping, 10.0);
}

TEST(BuiltinScenes, DrapeCornersHangsByRowZero) {
  const SceneSpec spec = builtin_scene("drape-corners");
  EXPECT_EQ(spec.lattice.rows, 25);
  EXPECT_EQ(spec.lattice.cols, 25);
  const ClothModel model = build_model(spec);
  ASSERT_EQ(model.anchor_count(), 2u);
  EXPECT_EQ(model.anchors[0].particle, 0u);
  EXPECT_EQ(model.anchors[1].particle, 24u);
  EXPECT_EQ(model.anchors[1].path.origin, (Vec3{12.0, 0.0, -12.0}));
  EXPECT_EQ(spec.environment.gravity, (Vec3{0.0, -9.81, 0.0}));
}

TEST(BuiltinScenes, FreeSpinFloatsAndSpins) {
  const SceneSpec spec = builtin_scene("free-spin");
  EXPECT_EQ(spec.lattice.rows, 11);
  EXPECT_EQ(spec.lattice.cols, 11);
  EXPECT_TRUE(spec.anchors.empty());
  EXPECT_EQ(spec.environment.gravity, (Vec3{0.0, 0.0, 0.0}));
  EXPECT_EQ(spec.initial.angular_velocity, (Vec3{0.3, 1.0, 0.2}));
  EXPECT_EQ(spec.initial.position_noise, 0.02);
  EXPECT_EQ(spec.initial.velocity_noise, 0.05);
  EXPECT_EQ(spec.initial.seed, 7u);
  EXPECT_EQ(spec.output.duration, 5.0);
  const ClothModel model = build_model(spec);
  const ClothState state = build_initial_state(model, spec);
  EXPECT_NE(state.velocity[0], (Vec3{}));
}

// pile is the scene self-collision is measured on at 50 x 50, 100 x 100 and 200 x 200 (issue 8):
// the lattice flags resize it, and its thickness stays below half the spacing of a 1 m sheet at
// 200 x 200, which a self-collision stage needs.
TEST(BuiltinScenes, PileResizesWithTheLatticeFlags) {
  const SceneSpec spec = builtin_scene("pile");
  EXPECT_EQ(spec.lattice.rows, 50);
  EXPECT_EQ(spec.lattice.cols, 50);
  EXPECT_TRUE(spec.anchors.empty()) << "anchors name rows and columns: they would not follow a resize";
  EXPECT_TRUE(spec.collision.self);
  EXPECT_LT(spec.collision.thickness, 0.5 * (1.0 / 199.0));
  ASSERT_TRUE(spec.material.has_value());

  // At the same spacing (a larger sheet of the same cotton) and at 1 m (the material set again).
  for (const bool one_metre : {false, true}) {
    SCOPED_TRACE(one_metre ? "1 m" : "same spacing");
    SceneSpec resized = spec;
    set_scene_field(resized, "lattice.rows", "200", "--set");
    set_scene_field(resized, "lattice.cols", "200", "--set");
    if (one_metre) {
      set_scene_field(resized, "lattice.spacing", "0.005025", "--set");
      set_scene_field(resized, "material", "cotton", "--set");
    }
    EXPECT_NO_THROW(validate_scene(resized, "pile"));
    const ClothModel model = build_model(resized);
    EXPECT_EQ(model.particle_count(), 40000u);
    EXPECT_EQ(model.colliders.size(), 2u);
    EXPECT_LT(model.collision.thickness, 0.5 * resized.lattice.spacing);
  }
}

}  // namespace
}  // namespace clothsim
