// The brute-force crossing check (sheet_crossings.h).
#include "sheet_crossings.h"

#include <algorithm>

namespace clothsim::testing {
namespace {

// Six times the signed volume of tetrahedron a-b-c-d: positive when d is on the side of plane
// a-b-c that its counter-clockwise normal points to.
double orient(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) { return dot(cross(b - a, c - a), d - a); }

// Whether the lattice connector between particles a and b (either order) exists and is intact,
// from the model's connector list: [particles] flags for the connector to the right (p, p+1) and
// the one below (p, p+cols).
struct LiveConnectors {
  std::vector<std::uint8_t> right;
  std::vector<std::uint8_t> down;

  explicit LiveConnectors(const ClothModel& model) : right(model.particle_count(), 0), down(model.particle_count(), 0) {
    const auto cols = static_cast<std::uint32_t>(model.cols);
    for (std::size_t e = 0; e < model.connector_count(); ++e) {
      const auto [first, second] = model.connector_particles[e];
      const std::uint32_t a = std::min(first, second);
      const std::uint32_t b = std::max(first, second);
      const std::uint8_t live = model.connector_live.empty() ? 1 : model.connector_live[e];
      if (b == a + 1 && b % cols != 0) right[a] = live;
      if (b == a + cols) down[a] = live;
    }
  }
};

// Axis-aligned bounding box, for the cheap reject before the volume test.
struct Box {
  Vec3 low;
  Vec3 high;
  void add(const Vec3& p) {
    low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
    high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
  }
  bool overlaps(const Box& other) const {
    return low.x <= other.high.x && other.low.x <= high.x && low.y <= other.high.y && other.low.y <= high.y &&
           low.z <= other.high.z && other.low.z <= high.z;
  }
};

Box box_of(std::span<const Vec3> position, std::span<const std::uint32_t> vertices) {
  Box box{position[vertices[0]], position[vertices[0]]};
  for (std::uint32_t v : vertices) box.add(position[v]);
  return box;
}

bool shares_particle(const std::array<std::uint32_t, 2>& edge, const std::array<std::uint32_t, 3>& triangle) {
  for (std::uint32_t v : triangle) {
    if (v == edge[0] || v == edge[1]) return true;
  }
  return false;
}

}  // namespace

SheetSurface sheet_surface(const ClothModel& model) {
  const LiveConnectors live(model);
  const auto cols = static_cast<std::uint32_t>(model.cols);
  SheetSurface surface;
  for (int row = 0; row + 1 < model.rows; ++row) {
    for (int col = 0; col + 1 < model.cols; ++col) {
      const std::uint32_t top_left = static_cast<std::uint32_t>(row) * cols + static_cast<std::uint32_t>(col);
      const std::uint32_t top_right = top_left + 1;
      const std::uint32_t bottom_left = top_left + cols;
      const std::uint32_t bottom_right = bottom_left + 1;
      // Each triangle's two connector edges; the third edge is the quad's diagonal.
      if (live.down[top_left] != 0 && live.right[top_left] != 0) {
        surface.triangles.push_back({top_left, bottom_left, top_right});
      }
      if (live.down[top_right] != 0 && live.right[bottom_left] != 0) {
        surface.triangles.push_back({top_right, bottom_left, bottom_right});
      }
    }
  }
  for (const auto& triangle : surface.triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = triangle[k];
      const std::uint32_t b = triangle[(k + 1) % 3];
      surface.edges.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  for (std::uint32_t p = 0; p < model.particle_count(); ++p) {
    if (live.right[p] != 0) surface.edges.push_back({p, p + 1});
    if (live.down[p] != 0) surface.edges.push_back({p, p + cols});
  }
  std::sort(surface.edges.begin(), surface.edges.end());
  surface.edges.erase(std::unique(surface.edges.begin(), surface.edges.end()), surface.edges.end());
  return surface;
}

bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  // p and q strictly on opposite sides of the triangle's plane ...
  const double side_p = orient(a, b, c, p);
  const double side_q = orient(a, b, c, q);
  if (!((side_p > 0.0 && side_q < 0.0) || (side_p < 0.0 && side_q > 0.0))) return false;
  // ... and line p-q passing strictly on the same side of each triangle edge (the three volumes
  // of p, q and an edge share a sign exactly when the line goes through the inside).
  const double around_ab = orient(p, q, a, b);
  const double around_bc = orient(p, q, b, c);
  const double around_ca = orient(p, q, c, a);
  return (around_ab > 0.0 && around_bc > 0.0 && around_ca > 0.0) ||
         (around_ab < 0.0 && around_bc < 0.0 && around_ca < 0.0);
}

std::vector<SheetCrossing> sheet_crossings(const ClothModel& model, std::span<const Vec3> position) {
  const SheetSurface surface = sheet_surface(model);
  std::vector<Box> triangle_box;
  triangle_box.reserve(surface.triangles.size());
  for (const auto& triangle : surface.triangles) triangle_box.push_back(box_of(position, triangle));

  std::vector<SheetCrossing> crossings;
  for (const auto& edge : surface.edges) {
    const Box edge_box = box_of(position, edge);
    for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
      const auto& triangle = surface.triangles[t];
      if (!edge_box.overlaps(triangle_box[t]) || shares_particle(edge, triangle)) continue;
      if (segment_crosses_triangle(position[edge[0]], position[edge[1]], position[triangle[0]], position[triangle[1]],
                                   position[triangle[2]])) {
        crossings.push_back({edge, triangle});
      }
    }
  }
  return crossings;
}

std::size_t count_sheet_crossings(const ClothModel& model, std::span<const Vec3> position) {
  return sheet_crossings(model, position).size();
}

}  // namespace clothsim::testing
