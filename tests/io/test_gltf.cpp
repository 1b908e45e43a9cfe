// Tests of io/gltf on its own: what write_glb does with a 1-wide lattice (lines, or points) and
// with bad paths and sizes; write_glb_animation of a chain. The mesh of a whole run, intact and
// torn, against final.obj and positions.npy is tested in test_run_exports.cpp (animation.glb's in
// test_run_exports_animation.cpp); the file is read by tinygltf's loader (glb_reader.h), not by
// the writer's code.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "glb_reader.h"
#include "io/gltf.h"
#include "model/model_edits.h"
#include "test_checks.h"

namespace clothsim {
namespace {

ClothModel make_sheet(int rows, int cols) {
  return build_lattice(LatticeDef{.rows = rows, .cols = cols, .spacing = 0.5}, Environment{}, {});
}

TEST(WriteGlb, SheetIsTrianglesWithNormalsAndBounds) {
  const ClothModel model = make_sheet(3, 4);
  const std::string path = checks::scratch_path("io", "sheet.glb");
  const GlbCounts counts = write_glb(path, model, model.particle_rest_position, GlbFrame{"flat", 7, 0.25});
  EXPECT_EQ(counts.vertices, 12u);
  EXPECT_EQ(counts.triangles, 12u);
  const testing::GlbMesh glb = testing::read_glb(path);
  ASSERT_TRUE(glb.loaded) << glb.error;
  EXPECT_TRUE(glb.error.empty()) << glb.error;  // no loader warnings either
  EXPECT_EQ(glb.mode, 4);
  EXPECT_EQ(glb.vertices(), 12u);
  EXPECT_EQ(glb.index.size(), 36u);
  EXPECT_EQ(glb.extras_frame, 7);
  EXPECT_EQ(glb.extras_time, 0.25);
  // The rest lattice lies in y = 0, facing +y, 1.5 m by 1 m about the origin.
  EXPECT_EQ(glb.position_min, (std::vector<double>{-0.75, 0.0, -0.5}));
  EXPECT_EQ(glb.position_max, (std::vector<double>{0.75, 0.0, 0.5}));
  ASSERT_EQ(glb.normal.size(), 36u);
  for (std::size_t v = 0; v < 12; ++v) EXPECT_EQ(glb.normal[3 * v + 1], 1.0f) << v;
}

// A sheet bent into an arc of a cylinder: the file's normals are the area-weighted normals of
// its own triangles (recomputed here from its positions and indices, in double), unit length, and
// within the triangulation's error of the cylinder's normal, facing out of it.
TEST(WriteGlb, ABentSheetsNormalsAreItsTrianglesAreaWeightedNormals) {
  const ClothModel model = make_sheet(7, 9);
  constexpr double kRadius = 4.0;  // the 4 m sheet spans an arc of 1 rad
  std::vector<Vec3> position = model.particle_rest_position;
  for (Vec3& x : position) x = {kRadius * std::sin(x.x / kRadius), kRadius * std::cos(x.x / kRadius) - kRadius, x.z};
  const std::string path = checks::scratch_path("io", "bent.glb");
  write_glb(path, model, position, GlbFrame{"bent", 1, 0.0});
  const testing::GlbMesh glb = testing::read_glb(path);
  ASSERT_TRUE(glb.loaded) << glb.error;
  const std::size_t vertices = glb.vertices();
  ASSERT_EQ(glb.normal.size(), 3 * vertices);
  const auto vertex = [&glb](std::uint32_t v) {
    return Vec3{glb.position[3 * v], glb.position[3 * v + 1], glb.position[3 * v + 2]};
  };
  std::vector<Vec3> expected(vertices);
  for (std::size_t t = 0; t + 2 < glb.index.size(); t += 3) {
    const Vec3 a = vertex(glb.index[t]);
    const Vec3 area_normal = cross(vertex(glb.index[t + 1]) - a, vertex(glb.index[t + 2]) - a);
    for (int corner = 0; corner < 3; ++corner) expected[glb.index[t + corner]] += area_normal;
  }
  for (std::size_t v = 0; v < vertices; ++v) {
    const Vec3 normal{glb.normal[3 * v], glb.normal[3 * v + 1], glb.normal[3 * v + 2]};
    const Vec3 brute = (1.0 / norm(expected[v])) * expected[v];
    EXPECT_NEAR(norm(normal), 1.0, 1e-6) << v;
    EXPECT_LT(norm(normal - brute), 1e-5) << "vertex " << v;
    // The cylinder's outward normal at the vertex: (x, y + R, 0) / R.
    const Vec3 x = vertex(static_cast<std::uint32_t>(v));
    const Vec3 cylinder{x.x / kRadius, (x.y + kRadius) / kRadius, 0.0};
    EXPECT_GT(dot(normal, cylinder), 0.99) << "vertex " << v;
  }
}

TEST(WriteGlb, OneWideLatticeIsLinesAlongItsConnectors) {
  for (const auto& [rows, cols] : {std::pair{1, 4}, std::pair{4, 1}}) {
    ClothModel model = make_sheet(rows, cols);
    const std::string path =
        checks::scratch_path("io", "strip_" + std::to_string(rows) + "x" + std::to_string(cols) + ".glb");
    EXPECT_EQ(write_glb(path, model, model.particle_rest_position).triangles, 0u);
    testing::GlbMesh glb = testing::read_glb(path);
    ASSERT_TRUE(glb.loaded) << glb.error;
    EXPECT_EQ(glb.mode, 1) << "lines";
    EXPECT_EQ(glb.vertices(), 4u);
    EXPECT_TRUE(glb.normal.empty());
    EXPECT_EQ(glb.index, (std::vector<std::uint32_t>{0, 1, 1, 2, 2, 3}));

    ASSERT_TRUE(break_connector(model, 1));  // between particles 1 and 2
    write_glb(path, model, model.particle_rest_position);
    glb = testing::read_glb(path);
    EXPECT_EQ(glb.index, (std::vector<std::uint32_t>{0, 1, 2, 3}));
  }
}

TEST(WriteGlb, StripWithEveryConnectorBrokenIsPoints) {
  ClothModel model = make_sheet(1, 2);
  ASSERT_TRUE(break_connector(model, 0));
  const std::string path = checks::scratch_path("io", "apart.glb");
  write_glb(path, model, model.particle_rest_position);
  const testing::GlbMesh glb = testing::read_glb(path);
  ASSERT_TRUE(glb.loaded) << glb.error;
  EXPECT_EQ(glb.mode, 0) << "points";
  EXPECT_EQ(glb.index, (std::vector<std::uint32_t>{0, 1}));
}

// animation.glb of a chain (a 1-wide lattice, lines without normals): its targets move positions
// only; frames come from the reader in order, twice (a pass for the bounds, one for the arrays);
// the targets' bounds are those of their values.
TEST(WriteGlbAnimation, ChainHasPositionTargetsOnlyAndReadsEachFrameTwice) {
  const ClothModel model = make_sheet(1, 4);
  const std::string path = checks::scratch_path("io", "chain_animation.glb");
  std::vector<std::size_t> read;
  const auto frame = [&read, &model](std::size_t k, std::span<Vec3> position) {
    read.push_back(k);
    for (std::size_t p = 0; p < position.size(); ++p) {
      position[p] = model.particle_rest_position[p] + Vec3{0.0, -0.1 * static_cast<double>(k * p), 0.0};
    }
  };
  const GlbCounts counts = write_glb_animation(path, model, GlbAnimation{"chain", 3, 10.0}, frame);
  EXPECT_EQ(counts.vertices, 4u);
  EXPECT_EQ(read, (std::vector<std::size_t>{0, 0, 1, 2, 0, 1, 2}));
  const testing::GlbMesh glb = testing::read_glb(path);
  ASSERT_TRUE(glb.loaded) << glb.error;
  EXPECT_TRUE(glb.error.empty()) << glb.error;
  EXPECT_EQ(glb.mode, 1) << "lines";
  EXPECT_EQ(glb.accessors_without_bounds, 0u);
  ASSERT_EQ(glb.target_position.size(), 3u);
  EXPECT_TRUE(glb.target_normal.empty());
  EXPECT_EQ(glb.target_position[2], (std::vector<float>{0, 0, 0, 0, -0.2f, 0, 0, -0.4f, 0, 0, -0.6f, 0}));
  EXPECT_EQ(glb.animation_time, (std::vector<float>{0.0f, 0.1f, 0.2f}));
  EXPECT_EQ(glb.animation_weight, (std::vector<float>{1, 0, 0, 0, 1, 0, 0, 0, 1}));
}

TEST(WriteGlb, ErrorsNameThePath) {
  checks::expect_write_errors_name_the_path([](const std::string& path, const ClothModel& model,
                                               std::span<const Vec3> position) { write_glb(path, model, position); },
                                            ".glb", "/dev/full: write failed");
}

}  // namespace
}  // namespace clothsim
