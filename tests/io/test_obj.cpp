// Tests of io/obj: the OBJ file read back line by line (counts, index ranges, values), including
// flipped, 1-wide and torn sheets. The triangulation and normals it writes are tested in
// tests/model/test_sheet_mesh.cpp.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "io/obj.h"
#include "model/model_edits.h"
#include "test_checks.h"
#include "test_support.h"

namespace clothsim {
namespace {

using checks::contains;
using checks::expect_near;
using testing::face_normal;

ClothModel make_sheet(int rows, int cols, double spacing = 0.5) {
  return build_lattice(LatticeDef{.rows = rows, .cols = cols, .spacing = spacing}, Environment{}, {});
}

// Rotation by 180 degrees about x: turns the sheet upside down (y -> -y, z -> -z).
Vec3 flip(const Vec3& p) { return {p.x, -p.y, -p.z}; }

// An OBJ file read back: one entry per line of each kind; indices as written (1-based).
struct ObjFile {
  std::vector<std::string> comments;   // text after "# "
  std::vector<std::string> objects;    // o names
  std::vector<std::string> smoothing;  // s arguments
  std::vector<Vec3> vertices;
  std::vector<std::array<double, 2>> texture_coordinates;
  std::vector<Vec3> normals;
  std::vector<std::array<std::array<long, 3>, 3>> faces;  // [corner][v, vt, vn]
  std::vector<std::vector<std::array<long, 2>>> lines;    // [point][v, vt]
  std::vector<std::string> unknown;                       // any other line
};

ObjFile read_obj(const std::string& path) {
  ObjFile obj;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string kind;
    fields >> kind;
    if (kind == "#") {
      obj.comments.push_back(line.size() > 2 ? line.substr(2) : "");
    } else if (kind == "o") {
      obj.objects.emplace_back();
      fields >> obj.objects.back();
    } else if (kind == "s") {
      obj.smoothing.emplace_back();
      fields >> obj.smoothing.back();
    } else if (kind == "v" || kind == "vn") {
      Vec3 value;
      fields >> value.x >> value.y >> value.z;
      (kind == "v" ? obj.vertices : obj.normals).push_back(value);
    } else if (kind == "vt") {
      std::array<double, 2> value{};
      fields >> value[0] >> value[1];
      obj.texture_coordinates.push_back(value);
    } else if (kind == "f") {
      std::array<std::array<long, 3>, 3> face{};
      char slash = 0;
      for (auto& corner : face) fields >> corner[0] >> slash >> corner[1] >> slash >> corner[2];
      if (fields.fail()) obj.unknown.push_back("unparsed: " + line);
      obj.faces.push_back(face);
      std::string extra;
      if (fields >> extra) obj.unknown.push_back("not a triangle: " + line);
      continue;
    } else if (kind == "l") {
      std::vector<std::array<long, 2>> points;
      std::array<long, 2> point{};
      char slash = 0;
      while (fields >> point[0] >> slash >> point[1]) points.push_back(point);
      obj.lines.push_back(points);
    } else {
      obj.unknown.push_back(line);
    }
    if (fields.fail() && kind != "#" && kind != "l") obj.unknown.push_back("unparsed: " + line);
  }
  return obj;
}

// --- The file ---

TEST(WriteObj, RestSheetReadsBack) {
  constexpr int rows = 3;
  constexpr int cols = 4;
  const ClothModel model = make_sheet(rows, cols, 0.5);
  const std::string path = checks::scratch_path("io", "rest_sheet.obj");
  write_obj(path, model, model.particle_rest_position, "scene: test\nframe 0, t = 0 s");
  const ObjFile obj = read_obj(path);

  EXPECT_TRUE(obj.unknown.empty()) << obj.unknown.front();
  ASSERT_GE(obj.comments.size(), 3U);
  EXPECT_TRUE(contains(obj.comments[0], "clothsim"));
  EXPECT_EQ(obj.comments[1], "scene: test");
  EXPECT_EQ(obj.comments[2], "frame 0, t = 0 s");
  EXPECT_EQ(obj.objects, (std::vector<std::string>{"clothsim_sheet"}));
  EXPECT_EQ(obj.smoothing, (std::vector<std::string>{"1"}));

  const std::size_t n = model.particle_count();
  ASSERT_EQ(obj.vertices.size(), n);
  ASSERT_EQ(obj.texture_coordinates.size(), n);
  ASSERT_EQ(obj.normals.size(), n);
  ASSERT_EQ(obj.faces.size(), 2U * (rows - 1) * (cols - 1));
  EXPECT_TRUE(obj.lines.empty());

  for (std::size_t p = 0; p < n; ++p) {
    expect_near(obj.vertices[p], model.particle_rest_position[p], 1e-9);
    const std::size_t row = p / cols;
    const std::size_t col = p % cols;
    EXPECT_NEAR(obj.texture_coordinates[p][0], static_cast<double>(col) / (cols - 1), 1e-9);
    EXPECT_NEAR(obj.texture_coordinates[p][1], static_cast<double>(row) / (rows - 1), 1e-9);
    EXPECT_NEAR(norm(obj.normals[p]), 1.0, 1e-8);
    expect_near(obj.normals[p], {0.0, 1.0, 0.0}, 1e-9);
  }
  for (const auto& face : obj.faces) {
    std::array<std::uint32_t, 3> triangle{};
    for (std::size_t corner = 0; corner < 3; ++corner) {
      const long index = face[corner][0];
      ASSERT_GE(index, 1);
      ASSERT_LE(index, static_cast<long>(n));
      EXPECT_EQ(face[corner][1], index) << "vt index";
      EXPECT_EQ(face[corner][2], index) << "vn index";
      triangle[corner] = static_cast<std::uint32_t>(index - 1);
    }
    EXPECT_GT(face_normal(obj.vertices, triangle).y, 0.0) << "faces wind counter-clockwise seen from +y";
  }
}

TEST(WriteObj, FlippedSheetHasDownwardNormalsAndFaces) {
  const ClothModel model = make_sheet(3, 4, 0.5);
  std::vector<Vec3> flipped;
  for (const Vec3& p : model.particle_rest_position) flipped.push_back(flip(p));
  const std::string path = checks::scratch_path("io", "flipped_sheet.obj");
  write_obj(path, model, flipped);
  const ObjFile obj = read_obj(path);
  ASSERT_EQ(obj.normals.size(), model.particle_count());
  for (const Vec3& normal : obj.normals) expect_near(normal, {0.0, -1.0, 0.0}, 1e-9);
  ASSERT_EQ(obj.faces.size(), 12U);
  for (const auto& face : obj.faces) {
    const std::array<std::uint32_t, 3> triangle = {static_cast<std::uint32_t>(face[0][0] - 1),
                                                   static_cast<std::uint32_t>(face[1][0] - 1),
                                                   static_cast<std::uint32_t>(face[2][0] - 1)};
    EXPECT_LT(face_normal(obj.vertices, triangle).y, 0.0);
  }
}

TEST(WriteObj, OneWideLatticeIsAPolyline) {
  for (const auto& [rows, cols] : {std::pair{1, 4}, std::pair{4, 1}}) {
    const ClothModel model = make_sheet(rows, cols);
    const std::string path =
        checks::scratch_path("io", "strip_" + std::to_string(rows) + "x" + std::to_string(cols) + ".obj");
    write_obj(path, model, model.particle_rest_position);
    const ObjFile obj = read_obj(path);
    EXPECT_TRUE(obj.unknown.empty()) << obj.unknown.front();
    EXPECT_EQ(obj.vertices.size(), 4U);
    EXPECT_EQ(obj.texture_coordinates.size(), 4U);
    EXPECT_TRUE(obj.faces.empty());
    EXPECT_TRUE(obj.normals.empty());
    ASSERT_EQ(obj.lines.size(), 1U);
    ASSERT_EQ(obj.lines[0].size(), 4U);
    for (std::size_t k = 0; k < 4; ++k) {
      EXPECT_EQ(obj.lines[0][k][0], static_cast<long>(k + 1));
      EXPECT_EQ(obj.lines[0][k][1], static_cast<long>(k + 1));
      for (const double coordinate : obj.texture_coordinates[k]) {
        EXPECT_TRUE(coordinate >= 0.0 && coordinate <= 1.0) << coordinate;
      }
    }
  }
}

TEST(WriteObj, TornSheetHasSplitVerticesAndReadsBack) {
  constexpr int rows = 4;
  constexpr int cols = 5;
  ClothModel model = make_sheet(rows, cols, 0.5);
  // A tear across the sheet between rows 1 and 2: the connectors from (1, j) south to (2, j).
  for (std::uint32_t e = 0; e < model.connector_count(); ++e) {
    const auto [a, b] = model.connector_particles[e];
    if (a / cols == 1 && b == a + cols) {
      ASSERT_TRUE(break_connector(model, e));
    }
  }
  std::vector<Vec3> position = model.particle_rest_position;
  for (std::size_t p = 2 * cols; p < position.size(); ++p) position[p].z += 0.4;  // the lower part moves away
  const std::string path = checks::scratch_path("io", "torn_sheet.obj");
  write_obj(path, model, position, "torn");
  const ObjFile obj = read_obj(path);
  EXPECT_TRUE(obj.unknown.empty()) << obj.unknown.front();
  ASSERT_GE(obj.comments.size(), 3U);
  EXPECT_TRUE(contains(obj.comments[1], "torn along 5 broken connectors"));
  EXPECT_EQ(obj.comments[2], "torn");

  SheetMesh mesh;
  build_sheet_mesh(model, position, SheetMeshMode::particles, mesh);
  const std::size_t n = model.particle_count();
  ASSERT_GT(mesh.vertex_count(), n);
  ASSERT_EQ(obj.vertices.size(), mesh.vertex_count());
  ASSERT_EQ(obj.texture_coordinates.size(), mesh.vertex_count());
  ASSERT_EQ(obj.normals.size(), mesh.vertex_count());
  ASSERT_EQ(obj.faces.size(), mesh.triangle_vertices.size());
  for (std::size_t p = 0; p < n; ++p) expect_near(obj.vertices[p], position[p], 1e-9);
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    expect_near(obj.vertices[v], mesh.vertex_position[v], 1e-8);
    EXPECT_NEAR(norm(obj.normals[v]), 1.0, 1e-8);
    for (const double coordinate : obj.texture_coordinates[v]) EXPECT_TRUE(coordinate >= 0.0 && coordinate <= 1.0);
  }
  // The two halves of a broken connector are two vertices, 0.4 m apart (half a rest length each
  // from their ends, which are 0.9 m apart).
  std::size_t halves = 0;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    if (mesh.vertex_source[v].kind != SheetVertexKind::connector_end || mesh.vertex_source[v].side != 0) continue;
    for (std::size_t w = 0; w < mesh.vertex_count(); ++w) {
      if (mesh.vertex_source[w].kind == SheetVertexKind::connector_end &&
          mesh.vertex_source[w].index == mesh.vertex_source[v].index && mesh.vertex_source[w].side == 1) {
        EXPECT_NEAR(norm(obj.vertices[w] - obj.vertices[v]), 0.4, 1e-8);
        ++halves;
      }
    }
  }
  EXPECT_EQ(halves, 5U);
  for (std::size_t f = 0; f < obj.faces.size(); ++f) {
    for (std::size_t corner = 0; corner < 3; ++corner) {
      EXPECT_EQ(obj.faces[f][corner][0], static_cast<long>(mesh.triangle_vertices[f][corner]) + 1);
      EXPECT_EQ(obj.faces[f][corner][1], obj.faces[f][corner][0]);
      EXPECT_EQ(obj.faces[f][corner][2], obj.faces[f][corner][0]);
    }
  }
}

TEST(WriteObj, TornStripIsOnePolylinePerPiece) {
  ClothModel model = make_sheet(1, 6);
  ASSERT_TRUE(break_connector(model, 2));  // between particles 2 and 3
  const std::string path = checks::scratch_path("io", "torn_strip.obj");
  write_obj(path, model, model.particle_rest_position);
  const ObjFile obj = read_obj(path);
  EXPECT_TRUE(obj.unknown.empty()) << obj.unknown.front();
  ASSERT_EQ(obj.lines.size(), 2U);
  EXPECT_EQ(obj.lines[0].size(), 3U);
  EXPECT_EQ(obj.lines[1].size(), 3U);
  EXPECT_EQ(obj.lines[1][0][0], 4);
}

TEST(WriteObj, ErrorsNameThePath) {
  checks::expect_write_errors_name_the_path([](const std::string& path, const ClothModel& model,
                                               std::span<const Vec3> position) { write_obj(path, model, position); },
                                            ".obj", "/dev/full: close failed: No space left on device");
}

}  // namespace
}  // namespace clothsim
