// Tests of model/sheet_mesh: the lattice triangulation and its winding, area-weighted vertex
// normals (rest, bumped, flipped, degenerate sheets), and the paper's cell-centre mesh (vertex
// count, positions at the centres of 4 particles, winding); torn sheets: no face spans a broken
// spring, no cloth disappears (the rest area is the sheet's), a tear along a line parts the mesh
// in two, normals do not average across a tear, broken halves open a gap, and the topology is
// rebuilt only when a connector breaks.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <set>
#include <vector>

#include "model/model_edits.h"
#include "model/sheet_mesh.h"
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
  for (const Vec3& normal : vertex_normals(model, flipped_rest, triangles))
    expect_near(normal, {0.0, -1.0, 0.0}, 1e-15);

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
      const Vec3 expected =
          (position[static_cast<std::size_t>(i * 6 + j)] + position[static_cast<std::size_t>(i * 6 + j + 1)] +
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

// --- Torn sheets ---

// The connector joining particles a and b, or kNoEdge.
std::uint32_t connector_between(const ClothModel& model, std::uint32_t a, std::uint32_t b) {
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    const auto [p, q] = model.connector_particles[e];
    if ((p == a && q == b) || (p == b && q == a)) return static_cast<std::uint32_t>(e);
  }
  return SheetMesh::kNoEdge;
}

// Breaks the connectors between rows `row` and `row` + 1: a tear straight across the sheet.
void tear_between_rows(ClothModel& model, int row) {
  for (int j = 0; j < model.cols; ++j) {
    ASSERT_TRUE(break_connector(
        model, connector_between(model, lattice_index(model.cols, row, j), lattice_index(model.cols, row + 1, j))));
  }
}

// Breaks about a third of the connectors, at random.
void tear_at_random(ClothModel& model, std::uint64_t seed) {
  testing::TestRandom random(seed);
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    if (random.uniform(0.0, 1.0) < 0.35) break_connector(model, static_cast<std::uint32_t>(e));
  }
}

// The particles a mesh vertex belongs to: its particle, both ends of an intact connector, the
// own end of a broken connector's half, the corners of a cell centre's component.
std::vector<std::uint32_t> vertex_particles(const ClothModel& model, const SheetVertexSource& source) {
  switch (source.kind) {
    case SheetVertexKind::particle: return {source.index};
    case SheetVertexKind::connector_midpoint:
      return {model.connector_particles[source.index][0], model.connector_particles[source.index][1]};
    case SheetVertexKind::connector_end: return {model.connector_particles[source.index][source.side]};
    case SheetVertexKind::cell_centre: {
      std::vector<std::uint32_t> particles;
      const int cell_row = static_cast<int>(source.index) / (model.cols - 1);
      const int cell_col = static_cast<int>(source.index) % (model.cols - 1);
      for (int k = 0; k < 4; ++k) {
        if ((source.corners & (1u << k)) == 0) continue;
        const auto& offset = kCellCorners[static_cast<std::size_t>(k)];
        particles.push_back(lattice_index(model.cols, cell_row + offset[0], cell_col + offset[1]));
      }
      return particles;
    }
  }
  return {};
}

// True when `particles` lie in one lattice cell and are connected through its intact edges.
bool joined_within_a_cell(const ClothModel& model, const std::set<std::uint32_t>& particles) {
  for (int i = 0; i + 1 < model.rows; ++i) {
    for (int j = 0; j + 1 < model.cols; ++j) {
      std::array<std::uint32_t, 4> corner{};
      for (std::size_t k = 0; k < 4; ++k) {
        corner[k] = lattice_index(model.cols, i + kCellCorners[k][0], j + kCellCorners[k][1]);
      }
      if (!std::all_of(particles.begin(), particles.end(),
                       [&](std::uint32_t p) { return std::find(corner.begin(), corner.end(), p) != corner.end(); })) {
        continue;
      }
      // Flood from one particle through the cell's live edges.
      std::set<std::uint32_t> reached = {*particles.begin()};
      for (int sweep = 0; sweep < 4; ++sweep) {
        for (std::size_t k = 0; k < 4; ++k) {
          const std::uint32_t a = corner[k];
          const std::uint32_t b = corner[(k + 1) % 4];
          if (model.connector_live[connector_between(model, a, b)] == 0) continue;
          if (reached.contains(a) || reached.contains(b)) reached.insert({a, b});
        }
      }
      if (std::all_of(particles.begin(), particles.end(), [&](std::uint32_t p) { return reached.contains(p); })) {
        return true;
      }
    }
  }
  return false;
}

double total_area(const SheetMesh& mesh) {
  double area = 0.0;
  for (const auto& triangle : mesh.triangle_vertices) area += 0.5 * norm(face_normal(mesh.vertex_position, triangle));
  return area;
}

// Connected pieces of the mesh: vertices joined by triangles (union-find), counting only vertices
// that some triangle uses.
std::size_t mesh_pieces(const SheetMesh& mesh) {
  std::vector<std::uint32_t> parent(mesh.vertex_count());
  std::iota(parent.begin(), parent.end(), 0u);
  const auto find = [&](std::uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  std::vector<std::uint8_t> used(mesh.vertex_count(), 0);
  for (const auto& triangle : mesh.triangle_vertices) {
    for (const std::uint32_t v : triangle) used[v] = 1;
    parent[find(triangle[1])] = find(triangle[0]);
    parent[find(triangle[2])] = find(triangle[0]);
  }
  std::set<std::uint32_t> roots;
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    if (used[v] != 0) roots.insert(find(v));
  }
  return roots.size();
}

TEST(TornSheetMesh, NoFaceSpansABrokenSpring) {
  for (const std::uint64_t seed : {1u, 2u, 3u, 4u}) {
    ClothModel model = make_sheet(6, 7);
    tear_at_random(model, seed);
    ASSERT_FALSE(model.is_intact());
    SheetMesh mesh;
    build_sheet_mesh(model, bumped_positions(model), SheetMeshMode::particles, mesh);
    ASSERT_EQ(mesh.vertex_source.size(), mesh.vertex_count());
    for (std::size_t p = 0; p < model.particle_count(); ++p) {
      EXPECT_EQ(mesh.vertex_source[p], (SheetVertexSource{SheetVertexKind::particle, static_cast<std::uint32_t>(p)}));
    }
    for (const auto& triangle : mesh.triangle_vertices) {
      std::set<std::uint32_t> particles;
      for (const std::uint32_t v : triangle) {
        for (const std::uint32_t p : vertex_particles(model, mesh.vertex_source[v])) particles.insert(p);
      }
      EXPECT_TRUE(joined_within_a_cell(model, particles))
          << "seed " << seed << ": triangle " << triangle[0] << " " << triangle[1] << " " << triangle[2];
    }
  }
}

TEST(TornSheetMesh, RestAreaIsTheSheetsAndFacesFaceUp) {
  for (const std::uint64_t seed : {5u, 6u, 7u}) {
    ClothModel model = make_sheet(5, 8, 0.5);
    tear_at_random(model, seed);
    SheetMesh mesh;
    build_sheet_mesh(model, model.particle_rest_position, SheetMeshMode::particles, mesh);
    EXPECT_NEAR(total_area(mesh), 4 * 7 * 0.25, 1e-12) << "seed " << seed;
    for (const auto& triangle : mesh.triangle_vertices) {
      const Vec3 normal = face_normal(mesh.vertex_position, triangle);
      EXPECT_GT(normal.y, 0.0);
      EXPECT_NEAR(norm(normal), normal.y, 1e-15);
    }
  }
}

TEST(TornSheetMesh, ATearAcrossTheSheetLeavesTwoPiecesAndNoHole) {
  constexpr int kRows = 5;
  constexpr int kCols = 6;
  constexpr double kSpacing = 0.4;
  ClothModel model = make_sheet(kRows, kCols, kSpacing);
  tear_between_rows(model, 2);
  SheetMesh mesh;
  build_sheet_mesh(model, model.particle_rest_position, SheetMeshMode::particles, mesh);
  EXPECT_NEAR(total_area(mesh), (kRows - 1) * (kCols - 1) * kSpacing * kSpacing, 1e-12);
  EXPECT_EQ(mesh_pieces(mesh), 2u);
  // The torn row of cells is 4 quarter cells each (8 triangles), the others stay 2 triangles.
  EXPECT_EQ(mesh.triangle_vertices.size(), static_cast<std::size_t>(2 * 3 * 5 + 8 * 5));
  // Split vertices: 2 halves per broken connector, 1 midpoint per intact edge of a torn cell,
  // 2 centre copies per torn cell.
  EXPECT_EQ(mesh.vertex_count(),
            static_cast<std::size_t>(kRows * kCols + 2 * kCols + 2 * (kCols - 1) + 2 * (kCols - 1)));
  // The cell-centre mode keeps its area too, in two pieces.
  SheetMesh cells;
  build_sheet_mesh(model, model.particle_rest_position, SheetMeshMode::cell_centres, cells);
  EXPECT_NEAR(total_area(cells), (kRows - 2) * (kCols - 2) * kSpacing * kSpacing, 1e-12);
  EXPECT_EQ(mesh_pieces(cells), 2u);
  EXPECT_EQ(cells.vertex_count(), static_cast<std::size_t>((kRows - 1) * (kCols - 1) + (kCols - 1)));
}

TEST(TornSheetMesh, HalvesOfABrokenConnectorOpenAGapAndNormalsKeepToTheirSide) {
  constexpr double kSpacing = 0.5;
  ClothModel model = make_sheet(4, 5, kSpacing);
  tear_between_rows(model, 1);
  // The lower part (rows 2 and 3) hangs down at 60 degrees below the upper part, moved 0.3 m
  // away from it: the torn connectors are stretched.
  std::vector<Vec3> position = model.particle_rest_position;
  const double hinge = position[lattice_index(model.cols, 2, 0)].z;
  for (int i = 2; i < 4; ++i) {
    for (int j = 0; j < 5; ++j) {
      Vec3& p = position[lattice_index(model.cols, i, j)];
      const double along = p.z - hinge;
      p = {p.x, -0.3 - along * std::sin(std::numbers::pi / 3), hinge + 0.3 + along * std::cos(std::numbers::pi / 3)};
    }
  }
  SheetMesh mesh;
  build_sheet_mesh(model, position, SheetMeshMode::particles, mesh);
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const SheetVertexSource& source = mesh.vertex_source[v];
    EXPECT_TRUE(is_finite(mesh.vertex_normal[v]));
    EXPECT_NEAR(norm(mesh.vertex_normal[v]), 1.0, 1e-12);
    if (source.kind == SheetVertexKind::connector_end) {
      // Half the rest length from its own end, towards the other.
      const auto [a, b] = model.connector_particles[source.index];
      const std::uint32_t own = source.side == 0 ? a : b;
      const std::uint32_t other = source.side == 0 ? b : a;
      EXPECT_NEAR(norm(mesh.vertex_position[v] - position[own]), 0.5 * kSpacing, 1e-12);
      EXPECT_NEAR(norm(mesh.vertex_position[v] - position[own]) + norm(position[other] - mesh.vertex_position[v]),
                  norm(position[other] - position[own]), 1e-12);
    }
    // The vertices of row 0, whose faces all lie in the flat upper part, keep the normal +y.
    const std::vector<std::uint32_t> particles = vertex_particles(model, source);
    if (std::all_of(particles.begin(), particles.end(), [&](std::uint32_t p) { return p < 5u; })) {
      expect_near(mesh.vertex_normal[v], {0.0, 1.0, 0.0}, 1e-12);
    }
  }
  // No vertex has faces on both sides of the tear, so no normal averages across it.
  std::vector<std::uint8_t> sides(mesh.vertex_count(), 0);  // bit 0: upper part, bit 1: lower part
  for (const auto& triangle : mesh.triangle_vertices) {
    std::uint8_t side = 0;
    for (const std::uint32_t v : triangle) {
      for (const std::uint32_t p : vertex_particles(model, mesh.vertex_source[v])) side |= p < 10u ? 1 : 2;
    }
    ASSERT_TRUE(side == 1 || side == 2) << "a face on both sides of the tear";
    for (const std::uint32_t v : triangle) sides[v] |= side;
  }
  for (const std::uint8_t side : sides) EXPECT_NE(side, 3);
  // Pushed together instead, both halves meet at the midpoint.
  std::vector<Vec3> squeezed = model.particle_rest_position;
  for (std::size_t p = 10; p < 20; ++p) squeezed[p].z -= 0.2;
  build_sheet_mesh(model, squeezed, SheetMeshMode::particles, mesh);
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    if (mesh.vertex_source[v].kind != SheetVertexKind::connector_end) continue;
    const auto [a, b] = model.connector_particles[mesh.vertex_source[v].index];
    expect_near(mesh.vertex_position[v], 0.5 * (squeezed[a] + squeezed[b]), 1e-15);
  }
}

TEST(TornSheetMesh, OneBrokenConnectorSlitsItsCellsWithoutSeparatingThem) {
  ClothModel model = make_sheet(3, 3);
  // The connector between the centre particle (1,1) and its east neighbour (1,2).
  ASSERT_TRUE(break_connector(model, connector_between(model, 4, 5)));
  SheetMesh mesh;
  build_sheet_mesh(model, model.particle_rest_position, SheetMeshMode::particles, mesh);
  EXPECT_EQ(mesh_pieces(mesh), 1u);
  std::size_t halves = 0;
  std::size_t centres = 0;
  for (const SheetVertexSource& source : mesh.vertex_source) {
    halves += source.kind == SheetVertexKind::connector_end ? 1 : 0;
    if (source.kind == SheetVertexKind::cell_centre) {
      ++centres;
      EXPECT_EQ(source.corners, 0xF) << "one broken edge leaves the cell in one piece";
    }
  }
  EXPECT_EQ(halves, 2u);
  EXPECT_EQ(centres, 2u);  // the two cells on either side of the connector
  EXPECT_NEAR(total_area(mesh), 4 * 0.25, 1e-12);
}

TEST(TornSheetMesh, CellComponentsFollowTheIntactEdges) {
  // One cell (2 x 2 particles): each set of broken edges gives the components of its corners
  // joined through the intact ones, one centre vertex each.
  const ClothModel intact = make_sheet(2, 2);
  // The cell's edges in kCellCorners order: (0,0)-(1,0), (1,0)-(1,1), (1,1)-(0,1), (0,1)-(0,0).
  const std::array<std::uint32_t, 4> edge = {connector_between(intact, 0, 2), connector_between(intact, 2, 3),
                                             connector_between(intact, 3, 1), connector_between(intact, 1, 0)};
  for (unsigned broken = 1; broken < 16; ++broken) {
    ClothModel model = intact;
    for (std::size_t k = 0; k < 4; ++k) {
      if ((broken & (1u << k)) != 0) {
        ASSERT_TRUE(break_connector(model, edge[k]));
      }
    }
    SheetMesh mesh;
    build_sheet_mesh(model, model.particle_rest_position, SheetMeshMode::particles, mesh);
    // Expected: corners k and k+1 are together when edge k is intact; count the arcs.
    const int broken_edges = std::popcount(broken);
    const std::size_t components = broken_edges <= 1 ? 1u : static_cast<std::size_t>(broken_edges);
    std::vector<std::uint8_t> centres;
    for (const SheetVertexSource& source : mesh.vertex_source) {
      if (source.kind == SheetVertexKind::cell_centre) centres.push_back(source.corners);
    }
    ASSERT_EQ(centres.size(), components) << "broken edges " << broken;
    std::uint8_t all = 0;
    for (const std::uint8_t corners : centres) {
      EXPECT_EQ(all & corners, 0) << "each corner in one component";
      all = static_cast<std::uint8_t>(all | corners);
      // Neighbouring corners in one component exactly when the edge between them is intact.
      for (std::size_t k = 0; k < 4; ++k) {
        const bool here = (corners & (1u << k)) != 0;
        const bool next = (corners & (1u << ((k + 1) % 4))) != 0;
        if (here && (broken & (1u << k)) == 0) {
          EXPECT_TRUE(next) << "broken edges " << broken;
        }
      }
    }
    EXPECT_EQ(all, 0xF);
    EXPECT_NEAR(total_area(mesh), 0.25, 1e-15);
  }
}

TEST(TornSheetMesh, CellCentreFacesKeepToTheirParticle) {
  ClothModel model = make_sheet(6, 6);
  tear_at_random(model, 11);
  SheetMesh mesh;
  build_sheet_mesh(model, bumped_positions(model), SheetMeshMode::cell_centres, mesh);
  EXPECT_EQ(mesh.grid_rows, 5);
  EXPECT_EQ(mesh.triangle_vertices.size(), 2u * 4u * 4u);
  for (const Vec3& normal : mesh.vertex_normal) EXPECT_TRUE(is_finite(normal));
  // Every face's vertices are copies of cell centres whose components share a particle.
  for (const auto& triangle : mesh.triangle_vertices) {
    std::vector<std::uint32_t> common = vertex_particles(model, mesh.vertex_source[triangle[0]]);
    for (std::size_t k = 1; k < 3; ++k) {
      const std::vector<std::uint32_t> particles = vertex_particles(model, mesh.vertex_source[triangle[k]]);
      std::erase_if(
          common, [&](std::uint32_t p) { return std::find(particles.begin(), particles.end(), p) == particles.end(); });
    }
    EXPECT_FALSE(common.empty());
  }
  // A cell with 4 intact edges sits at the mean of its corners, as on an intact sheet.
  const std::vector<Vec3> centre = cell_centre_positions(model, bumped_positions(model));
  for (std::uint32_t cell = 0; cell < 25; ++cell) {
    if (mesh.vertex_source[cell].corners == 0xF) expect_near(mesh.vertex_position[cell], centre[cell], 1e-12);
  }
}

TEST(TornSheetMesh, TopologyIsRebuiltOnlyWhenAConnectorBreaks) {
  ClothModel model = make_sheet(5, 5);
  SheetMesh mesh;
  build_sheet_mesh(model, model.particle_rest_position, SheetMeshMode::particles, mesh);
  const std::uint64_t intact_version = mesh.topology_version;
  EXPECT_EQ(mesh.triangle_vertices, lattice_triangles(model));
  ASSERT_TRUE(break_connector(model, 7));
  build_sheet_mesh(model, model.particle_rest_position, SheetMeshMode::particles, mesh);
  const std::uint64_t torn_version = mesh.topology_version;
  EXPECT_GT(torn_version, intact_version);
  const auto* triangles = mesh.triangle_vertices.data();
  const auto* positions = mesh.vertex_position.data();
  // Other edits (a rest length, as plasticity makes) move the revision, not the topology; new
  // positions reuse the arrays.
  set_connector_rest_length(model, 3, 0.9 * model.spacing);
  build_sheet_mesh(model, bumped_positions(model), SheetMeshMode::particles, mesh);
  EXPECT_EQ(mesh.topology_version, torn_version);
  EXPECT_EQ(mesh.triangle_vertices.data(), triangles);
  EXPECT_EQ(mesh.vertex_position.data(), positions);
  ASSERT_TRUE(break_connector(model, 12));
  build_sheet_mesh(model, model.particle_rest_position, SheetMeshMode::particles, mesh);
  EXPECT_GT(mesh.topology_version, torn_version);
  // A mesh that saw the torn model, given an intact one, goes back to the lattice's.
  const ClothModel intact = make_sheet(5, 5);
  build_sheet_mesh(intact, intact.particle_rest_position, SheetMeshMode::particles, mesh);
  EXPECT_EQ(mesh.triangle_vertices, lattice_triangles(intact));
  EXPECT_EQ(mesh.vertex_position, intact.particle_rest_position);
}

TEST(TornSheetMesh, VertexLatticeCoordinates) {
  ClothModel model = make_sheet(3, 4);
  tear_between_rows(model, 0);
  SheetMesh mesh;
  build_sheet_mesh(model, model.particle_rest_position, SheetMeshMode::particles, mesh);
  // At rest, every vertex sits where its lattice coordinates say.
  const Vec3 origin = model.particle_rest_position[0];
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const auto [row, col] = sheet_vertex_lattice_coordinate(model, mesh.vertex_source[v]);
    expect_near(mesh.vertex_position[v], origin + model.spacing * Vec3{col, 0.0, row}, 1e-12);
  }
}

}  // namespace
}  // namespace clothsim
