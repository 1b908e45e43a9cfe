// Tests of model/sheet_mesh: the lattice triangulation and its winding, area-weighted vertex
// normals (rest, bumped, flipped, degenerate sheets), and the paper's cell-centre mesh (vertex
// count, positions at the centres of 4 particles, winding).
#include "model/sheet_mesh.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "test_checks.h"
#include "test_support.h"

namespace clothsim {
namespace {

using checks::expect_near;
using testing::face_normal;

ClothModel make_sheet(int rows, int cols, double spacing = 0.5) {
  return build_lattice(LatticeDef{.rows = rows, .cols = cols, .spacing = spacing}, Environment{}, {});
}

// Rotation by 180 degrees about x: turns the sheet upside down (y -> -y, z -> -z).
Vec3 flip(const Vec3& p) { return {p.x, -p.y, -p.z}; }

// The rest lattice with a smooth bump: y = 0.3 L cos(x) cos(z), normals everywhere near +y.
std::vector<Vec3> bumped_positions(const ClothModel& model) {
  std::vector<Vec3> position = model.particle_rest_position;
  for (Vec3& p : position) p.y = 0.3 * model.spacing * std::cos(p.x) * std::cos(p.z);
  return position;
}

// --- Triangulation and normals ---

TEST(LatticeTriangles, CoverTheSheetWoundTowardsPlusY) {
  const ClothModel model = make_sheet(3, 4, 0.5);
  const auto triangles = lattice_triangles(model);
  ASSERT_EQ(triangles.size(), 2U * 2U * 3U);
  std::vector<int> uses(model.particle_count(), 0);
  double total_area = 0.0;
  for (const auto& triangle : triangles) {
    for (const std::uint32_t corner : triangle) {
      ASSERT_LT(corner, model.particle_count());
      ++uses[corner];
    }
    const Vec3 normal = face_normal(model.particle_rest_position, triangle);
    // cross(+z L, +x L) = +y L^2: area L^2 / 2, pointing up.
    expect_near(normal, {0.0, 0.25, 0.0}, 1e-15);
    total_area += 0.5 * norm(normal);
  }
  EXPECT_NEAR(total_area, 2 * 3 * 0.25, 1e-14);
  for (std::size_t p = 0; p < uses.size(); ++p) EXPECT_GT(uses[p], 0) << model.describe_particle(p);
  // First quad: (0,0) -> (1,0) -> (0,1), then (0,1) -> (1,0) -> (1,1).
  EXPECT_EQ(triangles[0], (std::array<std::uint32_t, 3>{0, 4, 1}));
  EXPECT_EQ(triangles[1], (std::array<std::uint32_t, 3>{1, 4, 5}));
}

TEST(LatticeTriangles, OneWideLatticesHaveNone) {
  EXPECT_TRUE(lattice_triangles(make_sheet(1, 5)).empty());
  EXPECT_TRUE(lattice_triangles(make_sheet(5, 1)).empty());
}

TEST(VertexNormals, UnitAndUpOnARestAndABumpedSheet) {
  const ClothModel model = make_sheet(6, 7, 0.5);
  const auto triangles = lattice_triangles(model);
  for (const Vec3& normal : vertex_normals(model, model.particle_rest_position, triangles)) {
    expect_near(normal, {0.0, 1.0, 0.0}, 1e-15);
  }
  const std::vector<Vec3> bumped = bumped_positions(model);
  const std::vector<Vec3> normals = vertex_normals(model, bumped, triangles);
  for (std::size_t p = 0; p < normals.size(); ++p) {
    EXPECT_NEAR(norm(normals[p]), 1.0, 1e-14) << model.describe_particle(p);
    EXPECT_GT(normals[p].y, 0.9) << model.describe_particle(p);
  }
  // A tent over a 3 x 3 lattice is symmetric under a half-turn about y, and so is the mesh (the
  // half-turn maps each quad's diagonal to a diagonal): the apex normal is exactly +y.
  const ClothModel small = make_sheet(3, 3, 1.0);
  std::vector<Vec3> tent = small.particle_rest_position;
  tent[4].y = 0.5;
  expect_near(vertex_normals(small, tent, lattice_triangles(small))[4], {0.0, 1.0, 0.0}, 1e-15);
}

TEST(VertexNormals, WeightFacesByArea) {
  // Particle 1 of a 2 x 3 lattice touches triangles (0,3,1), (1,3,4) and (1,4,2). Stretching the
  // second column and tilting particle 2 gives the faces different areas and normals.
  const ClothModel model = make_sheet(2, 3, 1.0);
  std::vector<Vec3> position = model.particle_rest_position;
  position[2] = {4.0, 1.0, -0.5};
  position[5] = {4.0, 0.0, 0.5};
  const auto triangles = lattice_triangles(model);
  Vec3 weighted;
  Vec3 unweighted;
  for (const auto& triangle : triangles) {
    if (triangle[0] != 1 && triangle[1] != 1 && triangle[2] != 1) continue;
    const Vec3 area_normal = face_normal(position, triangle);
    weighted += area_normal;
    unweighted += area_normal / norm(area_normal);
  }
  weighted = weighted / norm(weighted);
  unweighted = unweighted / norm(unweighted);
  ASSERT_GT(norm(weighted - unweighted), 1e-3) << "the test must tell the two weightings apart";
  expect_near(vertex_normals(model, position, triangles)[1], weighted, 1e-15);
}

TEST(VertexNormals, FlippedSheetPointsDown) {
  const ClothModel model = make_sheet(4, 5, 0.5);
  const auto triangles = lattice_triangles(model);
  std::vector<Vec3> flipped_rest;
  for (const Vec3& p : model.particle_rest_position) flipped_rest.push_back(flip(p));
  for (const Vec3& normal : vertex_normals(model, flipped_rest, triangles)) expect_near(normal, {0.0, -1.0, 0.0}, 1e-15);

  // Normals turn with the sheet: the flipped bump's normals are the flipped normals.
  const std::vector<Vec3> bumped = bumped_positions(model);
  std::vector<Vec3> flipped_bump;
  for (const Vec3& p : bumped) flipped_bump.push_back(flip(p));
  const std::vector<Vec3> up = vertex_normals(model, bumped, triangles);
  const std::vector<Vec3> down = vertex_normals(model, flipped_bump, triangles);
  for (std::size_t p = 0; p < up.size(); ++p) expect_near(down[p], flip(up[p]), 1e-14);
}

TEST(VertexNormals, DegenerateAndNonFiniteFallBackToPlusY) {
  const ClothModel model = make_sheet(3, 3);
  const auto triangles = lattice_triangles(model);
  const std::vector<Vec3> collapsed(model.particle_count(), Vec3{1.0, 2.0, 3.0});
  for (const Vec3& normal : vertex_normals(model, collapsed, triangles)) EXPECT_EQ(normal, (Vec3{0.0, 1.0, 0.0}));
  std::vector<Vec3> broken = model.particle_rest_position;
  broken[0].x = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Vec3> normals = vertex_normals(model, broken, triangles);
  for (const Vec3& normal : normals) EXPECT_TRUE(is_finite(normal));
  EXPECT_EQ(normals[0], (Vec3{0.0, 1.0, 0.0}));
  expect_near(normals[8], {0.0, 1.0, 0.0}, 1e-15);  // far corner: no NaN face touches it
}

// --- The paper's cell-centre mesh ---

TEST(CellCentreMesh, OneVertexPerCellAtTheMeanOfItsFourParticles) {
  const ClothModel model = make_sheet(4, 6, 0.5);
  // A non-planar, non-uniform configuration, so a wrong corner or weight shows.
  std::vector<Vec3> position = model.particle_rest_position;
  for (std::size_t p = 0; p < position.size(); ++p) {
    const auto k = static_cast<double>(p);
    position[p] += Vec3{0.01 * k, 0.1 * std::sin(k), 0.003 * k * k};
  }
  SheetMesh mesh;
  build_sheet_mesh(model, position, SheetMeshMode::cell_centres, mesh);
  EXPECT_EQ(mesh.grid_rows, 3);
  EXPECT_EQ(mesh.grid_cols, 5);
  ASSERT_EQ(mesh.vertex_position.size(), 15u);
  ASSERT_EQ(mesh.vertex_normal.size(), 15u);
  EXPECT_EQ(mesh.triangle_vertices.size(), 2u * 2u * 4u);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 5; ++j) {
      const Vec3 expected = (position[static_cast<std::size_t>(i * 6 + j)] + position[static_cast<std::size_t>(i * 6 + j + 1)] +
                             position[static_cast<std::size_t>((i + 1) * 6 + j)] +
                             position[static_cast<std::size_t>((i + 1) * 6 + j + 1)]) /
                            4.0;
      expect_near(mesh.vertex_position[static_cast<std::size_t>(i * 5 + j)], expected, 1e-15);
    }
  }
  EXPECT_EQ(cell_centre_positions(model, position), mesh.vertex_position);
}

TEST(CellCentreMesh, RestSheetIsHalfACellSmallerOnEverySideAndFacesUp) {
  const double spacing = 0.5;
  const ClothModel model = make_sheet(5, 5, spacing);
  SheetMesh mesh;
  build_sheet_mesh(model, model.particle_rest_position, SheetMeshMode::cell_centres, mesh);
  ASSERT_EQ(mesh.vertex_position.size(), 16u);
  // The lattice spans [-1, 1] in x and z; the cell centres span [-0.75, 0.75].
  expect_near(mesh.vertex_position.front(), {-0.75, 0.0, -0.75}, 1e-15);
  expect_near(mesh.vertex_position.back(), {0.75, 0.0, 0.75}, 1e-15);
  for (const auto& triangle : mesh.triangle_vertices) EXPECT_GT(face_normal(mesh.vertex_position, triangle).y, 0.0);
  for (const Vec3& normal : mesh.vertex_normal) expect_near(normal, {0.0, 1.0, 0.0}, 1e-15);
  // No vertex at the centre particle, where the paper's scenes anchor: it is a corner of 4 cells.
  for (const Vec3& vertex : mesh.vertex_position) EXPECT_GT(norm(vertex), 0.3);
}

TEST(CellCentreMesh, OneWideLatticeHasNoCells) {
  SheetMesh mesh;
  const ClothModel model = make_sheet(1, 5);
  build_sheet_mesh(model, model.particle_rest_position, SheetMeshMode::cell_centres, mesh);
  EXPECT_TRUE(mesh.vertex_position.empty());
  EXPECT_TRUE(mesh.triangle_vertices.empty());
}

TEST(SheetMesh, ParticleModeIsTheLatticeAndRebuildsOnModeChange) {
  const ClothModel model = make_sheet(3, 4);
  const std::vector<Vec3> bumped = bumped_positions(model);
  SheetMesh mesh;
  build_sheet_mesh(model, bumped, SheetMeshMode::particles, mesh);
  EXPECT_EQ(mesh.vertex_position, bumped);
  EXPECT_EQ(mesh.triangle_vertices, lattice_triangles(model));
  EXPECT_EQ(mesh.vertex_normal, vertex_normals(model, bumped, lattice_triangles(model)));
  build_sheet_mesh(model, bumped, SheetMeshMode::cell_centres, mesh);
  EXPECT_EQ(mesh.vertex_position.size(), 6u);
  EXPECT_EQ(mesh.triangle_vertices, grid_triangles(2, 3));
}

}  // namespace
}  // namespace clothsim
