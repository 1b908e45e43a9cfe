// Tests of io/gltf on its own: what write_glb does with a 1-wide lattice (lines, or points) and
// with bad paths and sizes. The mesh of a whole run, intact and torn, against final.obj and
// positions.npy is tested in test_run_exports.cpp; the file is read by tinygltf's loader
// (glb_reader.h), not by the writer's code.
#include <gtest/gtest.h>

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

TEST(WriteGlb, ErrorsNameThePath) {
  checks::expect_write_errors_name_the_path([](const std::string& path, const ClothModel& model,
                                               std::span<const Vec3> position) { write_glb(path, model, position); },
                                            ".glb", "/dev/full: write failed");
}

}  // namespace
}  // namespace clothsim
