// Lattice triangulation, cell-centre meshes and vertex normals; the conventions are in sheet_mesh.h.
#include "model/sheet_mesh.h"

#include <cmath>

#include "core/assert.h"

namespace clothsim {

std::vector<std::array<std::uint32_t, 3>> grid_triangles(int grid_rows, int grid_cols) {
  std::vector<std::array<std::uint32_t, 3>> triangles;
  if (grid_rows < 2 || grid_cols < 2) return triangles;
  triangles.reserve(2 * static_cast<std::size_t>(grid_rows - 1) * static_cast<std::size_t>(grid_cols - 1));
  for (int i = 0; i + 1 < grid_rows; ++i) {
    for (int j = 0; j + 1 < grid_cols; ++j) {
      const std::uint32_t top_left = lattice_index(grid_cols, i, j);
      const std::uint32_t top_right = lattice_index(grid_cols, i, j + 1);
      const std::uint32_t bottom_left = lattice_index(grid_cols, i + 1, j);
      const std::uint32_t bottom_right = lattice_index(grid_cols, i + 1, j + 1);
      // At rest: cross(+z L, +x L) = +y L^2 for the first, likewise for the second (sheet_mesh.h).
      triangles.push_back({top_left, bottom_left, top_right});
      triangles.push_back({top_right, bottom_left, bottom_right});
    }
  }
  return triangles;
}

std::vector<std::array<std::uint32_t, 3>> lattice_triangles(const ClothModel& model) {
  CLOTHSIM_ASSERT(model.rows >= 1 && model.cols >= 1 &&
                      static_cast<std::size_t>(model.rows) * static_cast<std::size_t>(model.cols) == model.particle_count(),
                  "the model is a rows x cols lattice");
  return grid_triangles(model.rows, model.cols);
}

namespace {

void compute_vertex_normals(std::span<const Vec3> position, std::span<const std::array<std::uint32_t, 3>> triangles,
                            std::vector<Vec3>& normal) {
  const std::size_t n = position.size();
  normal.assign(n, Vec3{});
  for (const auto& triangle : triangles) {
    CLOTHSIM_ASSERT(triangle[0] < n && triangle[1] < n && triangle[2] < n, "triangle indices name vertices");
    const Vec3& a = position[triangle[0]];
    // |cross| = 2 * area, so summing unnormalised cross products weights each face by its area.
    const Vec3 area_normal = cross(position[triangle[1]] - a, position[triangle[2]] - a);
    for (const std::uint32_t corner : triangle) normal[corner] += area_normal;
  }
  for (Vec3& vertex_normal : normal) {
    const double length = norm(vertex_normal);
    // length is 0 with no incident area, and inf/NaN for non-finite positions (or a squared
    // norm beyond 1e308): fall back to the rest normal rather than hand out NaNs.
    if (length > 0.0 && std::isfinite(length)) {
      vertex_normal = vertex_normal / length;
    } else {
      vertex_normal = Vec3{0.0, 1.0, 0.0};
    }
  }
}

}  // namespace

std::vector<Vec3> vertex_normals(std::span<const Vec3> position, std::span<const std::array<std::uint32_t, 3>> triangles) {
  std::vector<Vec3> normal;
  compute_vertex_normals(position, triangles, normal);
  return normal;
}

std::vector<Vec3> vertex_normals(const ClothModel& model, std::span<const Vec3> position,
                                 std::span<const std::array<std::uint32_t, 3>> triangles) {
  CLOTHSIM_ASSERT(position.size() == model.particle_count(), "one position per particle");
  return vertex_normals(position, triangles);
}

std::array<int, 2> sheet_mesh_grid(const ClothModel& model, SheetMeshMode mode) {
  if (mode == SheetMeshMode::particles) return {model.rows, model.cols};
  if (model.rows < 2 || model.cols < 2) return {0, 0};
  return {model.rows - 1, model.cols - 1};
}

namespace {

void fill_cell_centres(const ClothModel& model, std::span<const Vec3> position, std::vector<Vec3>& centre) {
  const auto [grid_rows, grid_cols] = sheet_mesh_grid(model, SheetMeshMode::cell_centres);
  centre.resize(static_cast<std::size_t>(grid_rows) * static_cast<std::size_t>(grid_cols));
  const int cols = model.cols;
  for (int i = 0; i < grid_rows; ++i) {
    for (int j = 0; j < grid_cols; ++j) {
      const Vec3 sum = position[lattice_index(cols, i, j)] + position[lattice_index(cols, i, j + 1)] +
                       position[lattice_index(cols, i + 1, j)] + position[lattice_index(cols, i + 1, j + 1)];
      centre[lattice_index(grid_cols, i, j)] = 0.25 * sum;
    }
  }
}

}  // namespace

std::vector<Vec3> cell_centre_positions(const ClothModel& model, std::span<const Vec3> position) {
  CLOTHSIM_ASSERT(position.size() == model.particle_count(), "one position per particle");
  std::vector<Vec3> centre;
  fill_cell_centres(model, position, centre);
  return centre;
}

void build_sheet_mesh(const ClothModel& model, std::span<const Vec3> position, SheetMeshMode mode, SheetMesh& mesh) {
  CLOTHSIM_ASSERT(position.size() == model.particle_count(), "one position per particle");
  const auto [grid_rows, grid_cols] = sheet_mesh_grid(model, mode);
  if (grid_rows != mesh.grid_rows || grid_cols != mesh.grid_cols || mesh.triangle_vertices.empty()) {
    mesh.grid_rows = grid_rows;
    mesh.grid_cols = grid_cols;
    mesh.triangle_vertices = grid_triangles(grid_rows, grid_cols);
  }
  if (mode == SheetMeshMode::particles) {
    mesh.vertex_position.assign(position.begin(), position.end());
  } else {
    fill_cell_centres(model, position, mesh.vertex_position);
  }
  compute_vertex_normals(mesh.vertex_position, mesh.triangle_vertices, mesh.vertex_normal);
}

}  // namespace clothsim
