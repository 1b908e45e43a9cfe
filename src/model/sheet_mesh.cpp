// Lattice triangulation, cell-centre meshes and vertex normals; the conventions are in sheet_mesh.h.
#include "model/sheet_mesh.h"

#include <algorithm>
#include <cmath>
#include <utility>

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
  CLOTHSIM_ASSERT(
      model.rows >= 1 && model.cols >= 1 &&
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

std::vector<Vec3> vertex_normals(std::span<const Vec3> position,
                                 std::span<const std::array<std::uint32_t, 3>> triangles) {
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

std::array<double, 2> sheet_vertex_lattice_coordinate(const ClothModel& model, const SheetVertexSource& source) {
  const int cols = std::max(model.cols, 1);
  const auto of_particle = [cols](std::uint32_t particle) {
    return std::array<double, 2>{static_cast<double>(particle / static_cast<std::uint32_t>(cols)),
                                 static_cast<double>(particle % static_cast<std::uint32_t>(cols))};
  };
  switch (source.kind) {
    case SheetVertexKind::particle: return of_particle(source.index);
    case SheetVertexKind::connector_midpoint:
    case SheetVertexKind::connector_end: {
      const auto [a, b] = model.connector_particles[source.index];
      const std::array<double, 2> at_a = of_particle(a);
      const std::array<double, 2> at_b = of_particle(b);
      return {0.5 * (at_a[0] + at_b[0]), 0.5 * (at_a[1] + at_b[1])};
    }
    case SheetVertexKind::cell_centre: {
      const int cell_cols = std::max(model.cols - 1, 1);
      const auto cell = static_cast<int>(source.index);
      return {cell / cell_cols + 0.5, cell % cell_cols + 0.5};
    }
  }
  return {0.0, 0.0};
}

namespace {

// --- Torn sheets (sheet_mesh.h) ---

// Fills mesh.cell_edge: the connector along each edge of each cell, found from the connector
// list, so any connector order works. A torn sheet is a lattice: every cell edge has its
// connector.
void find_cell_edges(const ClothModel& model, SheetMesh& mesh) {
  const int rows = model.rows;
  const int cols = model.cols;
  const std::size_t n = model.particle_count();
  // east[p], south[p]: the connector from particle p to its east and south neighbour.
  std::vector<std::uint32_t> east(n, SheetMesh::kNoEdge);
  std::vector<std::uint32_t> south(n, SheetMesh::kNoEdge);
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    auto [a, b] = model.connector_particles[e];
    if (a > b) std::swap(a, b);
    const auto col = static_cast<int>(a % static_cast<std::uint32_t>(cols));
    if (b == a + 1 && col + 1 < cols) east[a] = static_cast<std::uint32_t>(e);
    if (b == a + static_cast<std::uint32_t>(cols)) south[a] = static_cast<std::uint32_t>(e);
  }
  mesh.cell_edge.resize(static_cast<std::size_t>(rows - 1) * static_cast<std::size_t>(cols - 1));
  for (int i = 0; i + 1 < rows; ++i) {
    for (int j = 0; j + 1 < cols; ++j) {
      CLOTHSIM_ASSERT(east[lattice_index(cols, i, j)] != SheetMesh::kNoEdge &&
                          south[lattice_index(cols, i, j)] != SheetMesh::kNoEdge &&
                          east[lattice_index(cols, i + 1, j)] != SheetMesh::kNoEdge &&
                          south[lattice_index(cols, i, j + 1)] != SheetMesh::kNoEdge,
                      "a torn sheet has a connector along every lattice edge");
      // Edge k joins corner k and k+1 of kCellCorners: (i,j)-(i+1,j), (i+1,j)-(i+1,j+1),
      // (i+1,j+1)-(i,j+1), (i,j+1)-(i,j).
      mesh.cell_edge[lattice_index(cols - 1, i, j)] = {
          south[lattice_index(cols, i, j)], east[lattice_index(cols, i + 1, j)], south[lattice_index(cols, i, j + 1)],
          east[lattice_index(cols, i, j)]};
    }
  }
}

bool edge_live(const ClothModel& model, std::uint32_t connector) { return model.connector_live[connector] != 0; }

bool cell_intact(const ClothModel& model, const std::array<std::uint32_t, 4>& edge) {
  return edge_live(model, edge[0]) && edge_live(model, edge[1]) && edge_live(model, edge[2]) &&
         edge_live(model, edge[3]);
}

std::uint32_t cell_corner_particle(int cols, int cell_row, int cell_col, int corner) {
  const auto& offset = kCellCorners[static_cast<std::size_t>(corner)];
  return lattice_index(cols, cell_row + offset[0], cell_col + offset[1]);
}

// Component labels of a cell's 4 corners, joined through its intact edges: label[k] is the
// smallest corner index of corner k's component.
std::array<int, 4> cell_components(const ClothModel& model, const std::array<std::uint32_t, 4>& edge) {
  std::array<int, 4> label = {0, 1, 2, 3};
  // Spread the smallest label along intact edges until nothing changes (at most 4 sweeps of the
  // cycle of 4).
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t k = 0; k < 4; ++k) {
      const std::size_t next = (k + 1) % 4;
      if (!edge_live(model, edge[k]) || label[k] == label[next]) continue;
      label[k] = label[next] = std::min(label[k], label[next]);
      changed = true;
    }
  }
  return label;
}

std::uint8_t component_corners(const std::array<int, 4>& label, int component) {
  std::uint8_t corners = 0;
  for (int k = 0; k < 4; ++k) {
    if (label[static_cast<std::size_t>(k)] == component) corners = static_cast<std::uint8_t>(corners | (1u << k));
  }
  return corners;
}

// Where `from`'s half of connector `connector` ends: the midpoint for an intact connector, or,
// for a broken one, half its rest length (at most half its length) from `from` towards the
// other end.
Vec3 connector_half_end(const ClothModel& model, std::span<const Vec3> position, std::uint32_t connector,
                        std::uint32_t from) {
  const auto [a, b] = model.connector_particles[connector];
  const std::uint32_t to = from == a ? b : a;
  if (model.connector_live[connector] != 0) return 0.5 * (position[a] + position[b]);
  const Vec3 d = position[to] - position[from];
  const double length = norm(d);
  if (!(length > 0.0)) return position[from];
  const double half = 0.5 * std::min(length, model.connector_rest_length[connector]);
  return position[from] + (half / length) * d;
}

// The centre copy of cell `cell` for the corners in `corners`: the mean over them of
// m1 + m2 - x_p, m1 and m2 the ends of p's two edges on p's side; the mean of the 4 corners for
// a cell with 4 intact edges.
Vec3 cell_centre_copy(const ClothModel& model, const SheetMesh& mesh, std::span<const Vec3> position,
                      std::uint32_t cell, std::uint8_t corners) {
  const int cell_cols = model.cols - 1;
  const int cell_row = static_cast<int>(cell) / cell_cols;
  const int cell_col = static_cast<int>(cell) % cell_cols;
  const std::array<std::uint32_t, 4>& edge = mesh.cell_edge[cell];
  std::array<std::uint32_t, 4> corner{};
  for (int k = 0; k < 4; ++k) {
    corner[static_cast<std::size_t>(k)] = cell_corner_particle(model.cols, cell_row, cell_col, k);
  }
  if (corners == 0xF && cell_intact(model, edge)) {
    return 0.25 * (position[corner[0]] + position[corner[1]] + position[corner[2]] + position[corner[3]]);
  }
  Vec3 sum{};
  int count = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    if ((corners & (1u << k)) == 0) continue;
    const Vec3 m1 = connector_half_end(model, position, edge[k], corner[k]);
    const Vec3 m2 = connector_half_end(model, position, edge[(k + 3) % 4], corner[k]);
    sum += m1 + m2 - position[corner[k]];
    ++count;
  }
  return sum / static_cast<double>(count);
}

std::uint32_t add_vertex(SheetMesh& mesh, const SheetVertexSource& source) {
  mesh.vertex_source.push_back(source);
  return static_cast<std::uint32_t>(mesh.vertex_source.size() - 1);
}

// Particle-mode topology of a torn sheet (sheet_mesh.h).
void build_torn_particle_topology(const ClothModel& model, SheetMesh& mesh) {
  const int rows = model.rows;
  const int cols = model.cols;
  const std::size_t n = model.particle_count();
  mesh.vertex_source.clear();
  mesh.triangle_vertices.clear();
  for (std::size_t p = 0; p < n; ++p) add_vertex(mesh, {SheetVertexKind::particle, static_cast<std::uint32_t>(p)});
  // half_vertex[e][s]: the vertex of connector e's half at end s (both the midpoint if intact).
  std::vector<std::array<std::uint32_t, 2>> half_vertex(model.connector_count(),
                                                        {SheetMesh::kNoEdge, SheetMesh::kNoEdge});
  const auto edge_vertex = [&](std::uint32_t connector, std::uint32_t from) {
    const std::size_t side = model.connector_particles[connector][0] == from ? 0 : 1;
    std::uint32_t& vertex = half_vertex[connector][side];
    if (vertex != SheetMesh::kNoEdge) return vertex;
    if (model.connector_live[connector] != 0) {
      vertex = add_vertex(mesh, {SheetVertexKind::connector_midpoint, connector});
      half_vertex[connector][1 - side] = vertex;
    } else {
      vertex = add_vertex(mesh, {SheetVertexKind::connector_end, connector, static_cast<std::uint8_t>(side)});
    }
    return vertex;
  };
  for (int i = 0; i + 1 < rows; ++i) {
    for (int j = 0; j + 1 < cols; ++j) {
      const std::uint32_t cell = lattice_index(cols - 1, i, j);
      const std::array<std::uint32_t, 4>& edge = mesh.cell_edge[cell];
      std::array<std::uint32_t, 4> corner{};
      for (int k = 0; k < 4; ++k) corner[static_cast<std::size_t>(k)] = cell_corner_particle(cols, i, j, k);
      if (cell_intact(model, edge)) {
        // The intact quad's two triangles, as grid_triangles() cuts them.
        mesh.triangle_vertices.push_back({corner[0], corner[1], corner[3]});
        mesh.triangle_vertices.push_back({corner[3], corner[1], corner[2]});
        continue;
      }
      const std::array<int, 4> label = cell_components(model, edge);
      std::array<std::uint32_t, 4> centre{};
      for (std::size_t k = 0; k < 4; ++k) {
        if (label[k] != static_cast<int>(k)) continue;  // the component's first corner makes its vertex
        const std::uint8_t corners = component_corners(label, static_cast<int>(k));
        centre[k] = add_vertex(mesh, {SheetVertexKind::cell_centre, cell, 0, corners});
      }
      for (std::size_t k = 0; k < 4; ++k) {
        const std::uint32_t m1 = edge_vertex(edge[k], corner[k]);
        const std::uint32_t m2 = edge_vertex(edge[(k + 3) % 4], corner[k]);
        const std::uint32_t c = centre[static_cast<std::size_t>(label[k])];
        // At rest cross(m1 - p, c - p) and cross(c - p, m2 - p) point +y, like the intact triangles.
        mesh.triangle_vertices.push_back({corner[k], m1, c});
        mesh.triangle_vertices.push_back({corner[k], c, m2});
      }
    }
  }
}

// Cell-centre topology of a torn sheet (sheet_mesh.h): vertex q is cell q's copy for the
// component of its corner 0, further copies follow; interior particle P's face takes, in each of
// its 4 cells, the copy of P's component.
void build_torn_cell_topology(const ClothModel& model, SheetMesh& mesh) {
  const int cell_rows = model.rows - 1;
  const int cell_cols = model.cols - 1;
  const std::size_t cells = mesh.cell_edge.size();
  mesh.vertex_source.clear();
  mesh.triangle_vertices.clear();
  std::vector<std::array<int, 4>> label(cells);
  for (std::size_t cell = 0; cell < cells; ++cell) {
    label[cell] = cell_components(model, mesh.cell_edge[cell]);
    add_vertex(mesh,
               {SheetVertexKind::cell_centre, static_cast<std::uint32_t>(cell), 0, component_corners(label[cell], 0)});
  }
  // corner_vertex[cell][k]: the copy of cell's centre that holds its corner k.
  std::vector<std::array<std::uint32_t, 4>> corner_vertex(cells);
  for (std::size_t cell = 0; cell < cells; ++cell) {
    std::array<std::uint32_t, 4> component_vertex = {static_cast<std::uint32_t>(cell), 0, 0, 0};
    for (std::size_t k = 1; k < 4; ++k) {
      if (label[cell][k] != static_cast<int>(k)) continue;
      component_vertex[k] = add_vertex(mesh, {SheetVertexKind::cell_centre, static_cast<std::uint32_t>(cell), 0,
                                              component_corners(label[cell], static_cast<int>(k))});
    }
    for (std::size_t k = 0; k < 4; ++k) {
      corner_vertex[cell][k] = component_vertex[static_cast<std::size_t>(label[cell][k])];
    }
  }
  for (int i = 0; i + 1 < cell_rows; ++i) {
    for (int j = 0; j + 1 < cell_cols; ++j) {
      // Particle (i+1, j+1) is corner 2 of cell (i,j), 1 of (i,j+1), 3 of (i+1,j) and 0 of (i+1,j+1).
      const std::uint32_t top_left = corner_vertex[lattice_index(cell_cols, i, j)][2];
      const std::uint32_t top_right = corner_vertex[lattice_index(cell_cols, i, j + 1)][1];
      const std::uint32_t bottom_left = corner_vertex[lattice_index(cell_cols, i + 1, j)][3];
      const std::uint32_t bottom_right = corner_vertex[lattice_index(cell_cols, i + 1, j + 1)][0];
      mesh.triangle_vertices.push_back({top_left, bottom_left, top_right});
      mesh.triangle_vertices.push_back({top_right, bottom_left, bottom_right});
    }
  }
}

bool topology_changed(const ClothModel& model, SheetMeshMode mode, bool torn, const SheetMesh& mesh) {
  if (mesh.built_mode != mode || mesh.built_rows != model.rows || mesh.built_cols != model.cols ||
      mesh.built_connectors != model.connector_count() || mesh.built_torn != torn) {
    return true;
  }
  return torn && !std::equal(mesh.built_live.begin(), mesh.built_live.end(), model.connector_live.begin());
}

void build_topology(const ClothModel& model, SheetMeshMode mode, bool torn, SheetMesh& mesh) {
  const auto [grid_rows, grid_cols] = sheet_mesh_grid(model, mode);
  mesh.grid_rows = grid_rows;
  mesh.grid_cols = grid_cols;
  mesh.built_mode = mode;
  mesh.built_rows = model.rows;
  mesh.built_cols = model.cols;
  mesh.built_connectors = model.connector_count();
  mesh.built_torn = torn;
  ++mesh.topology_version;
  if (torn) {
    find_cell_edges(model, mesh);
    mesh.built_live = model.connector_live;
    if (mode == SheetMeshMode::particles) {
      build_torn_particle_topology(model, mesh);
    } else {
      build_torn_cell_topology(model, mesh);
    }
    return;
  }
  mesh.built_live.clear();
  mesh.cell_edge.clear();
  mesh.triangle_vertices = grid_triangles(grid_rows, grid_cols);
  const auto vertices = static_cast<std::uint32_t>(grid_rows * grid_cols);
  mesh.vertex_source.resize(vertices);
  for (std::uint32_t v = 0; v < vertices; ++v) {
    mesh.vertex_source[v] = mode == SheetMeshMode::particles
                                ? SheetVertexSource{SheetVertexKind::particle, v}
                                : SheetVertexSource{SheetVertexKind::cell_centre, v, 0, 0xF};
  }
}

}  // namespace

void build_sheet_mesh(const ClothModel& model, std::span<const Vec3> position, SheetMeshMode mode, SheetMesh& mesh) {
  CLOTHSIM_ASSERT(position.size() == model.particle_count(), "one position per particle");
  // A 1-wide lattice has no faces to split.
  const bool torn = !model.is_intact() && model.rows >= 2 && model.cols >= 2;
  if (topology_changed(model, mode, torn, mesh)) build_topology(model, mode, torn, mesh);
  if (!torn) {
    if (mode == SheetMeshMode::particles) {
      mesh.vertex_position.assign(position.begin(), position.end());
    } else {
      fill_cell_centres(model, position, mesh.vertex_position);
    }
  } else {
    mesh.vertex_position.resize(mesh.vertex_source.size());
    for (std::size_t v = 0; v < mesh.vertex_source.size(); ++v) {
      const SheetVertexSource& source = mesh.vertex_source[v];
      Vec3& at = mesh.vertex_position[v];
      switch (source.kind) {
        case SheetVertexKind::particle: at = position[source.index]; break;
        case SheetVertexKind::connector_midpoint: {
          const auto [a, b] = model.connector_particles[source.index];
          at = 0.5 * (position[a] + position[b]);
          break;
        }
        case SheetVertexKind::connector_end:
          at = connector_half_end(model, position, source.index, model.connector_particles[source.index][source.side]);
          break;
        case SheetVertexKind::cell_centre:
          at = cell_centre_copy(model, mesh, position, source.index, source.corners);
          break;
      }
    }
  }
  compute_vertex_normals(mesh.vertex_position, mesh.triangle_vertices, mesh.vertex_normal);
}

}  // namespace clothsim
