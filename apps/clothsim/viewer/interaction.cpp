#include "viewer/interaction.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace clothsim::viewer {

long pick_particle(const render::Camera& camera, std::span<const Vec3> positions, double x, double y, int width,
                   int height, double radius) {
  // One matrix for all particles (Camera::project would rebuild it per point), and the same
  // projection as Camera::project: clip space, then pixels with y down.
  const render::Mat4 matrix = camera.view_projection(static_cast<double>(width) / height);
  long best = -1;
  double best_distance = radius;
  double best_depth = 0.0;
  for (std::size_t p = 0; p < positions.size(); ++p) {
    const Vec3& point = positions[p];
    const auto row = [&](int r) {
      return matrix(r, 0) * point.x + matrix(r, 1) * point.y + matrix(r, 2) * point.z + matrix(r, 3);
    };
    const double w = row(3);
    if (!(w > 0.0)) continue;  // behind the eye
    const double ndc_x = row(0) / w;
    const double ndc_y = row(1) / w;
    const double depth = row(2) / w;
    if (std::abs(ndc_x) > 1.0 || std::abs(ndc_y) > 1.0 || std::abs(depth) > 1.0) continue;
    const double distance = std::hypot((ndc_x + 1.0) / 2.0 * width - x, (1.0 - ndc_y) / 2.0 * height - y);
    if (distance > radius) continue;
    // Within a tenth of a pixel counts as the same distance: then the nearer particle wins.
    const bool closer = distance < best_distance - 0.1;
    const bool tie_nearer = distance <= best_distance + 0.1 && depth < best_depth;
    if (best < 0 || closer || tie_nearer) {
      best = static_cast<long>(p);
      best_distance = distance;
      best_depth = depth;
    }
  }
  return best;
}

std::optional<Vec3> drag_target(const render::Camera& camera, const Vec3& plane_point, double x, double y, int width,
                                int height) {
  const render::Ray ray = camera.pick_ray(x, y, width, height);
  const Vec3 normal = camera.forward();
  const double facing = dot(ray.direction, normal);
  if (std::abs(facing) < 1e-9) return std::nullopt;
  const double t = dot(plane_point - ray.origin, normal) / facing;
  if (!(t > 0.0)) return std::nullopt;
  return ray.origin + t * ray.direction;
}

namespace {

using Point = std::array<double, 2>;

// (b - a) x (c - a): > 0 when c is left of a->b.
double orientation(const Point& a, const Point& b, const Point& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

bool on_segment(const Point& a, const Point& b, const Point& c) {
  return std::min(a[0], b[0]) <= c[0] && c[0] <= std::max(a[0], b[0]) && std::min(a[1], b[1]) <= c[1] &&
         c[1] <= std::max(a[1], b[1]);
}

// Whether segments p1-p2 and q1-q2 share a point (the textbook orientation test, with the
// collinear cases).
bool segments_cross(const Point& p1, const Point& p2, const Point& q1, const Point& q2) {
  const double d1 = orientation(q1, q2, p1);
  const double d2 = orientation(q1, q2, p2);
  const double d3 = orientation(p1, p2, q1);
  const double d4 = orientation(p1, p2, q2);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  return (d1 == 0 && on_segment(q1, q2, p1)) || (d2 == 0 && on_segment(q1, q2, p2)) ||
         (d3 == 0 && on_segment(p1, p2, q1)) || (d4 == 0 && on_segment(p1, p2, q2));
}

}  // namespace

std::vector<std::uint32_t> connectors_crossed(const ClothModel& model, std::span<const std::array<double, 2>> point,
                                              const std::array<double, 2>& from, const std::array<double, 2>& to) {
  std::vector<std::uint32_t> crossed;
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    if (model.connector_live[e] == 0) continue;
    const auto [a, b] = model.connector_particles[e];
    const Point& pa = point[a];
    const Point& pb = point[b];
    if (std::isnan(pa[0]) || std::isnan(pb[0])) continue;
    if (segments_cross(pa, pb, from, to)) crossed.push_back(static_cast<std::uint32_t>(e));
  }
  return crossed;
}

std::vector<std::uint32_t> connectors_crossed_on_screen(const render::Camera& camera, const ClothModel& model,
                                                        std::span<const Vec3> positions, double x0, double y0,
                                                        double x1, double y1, int width, int height) {
  // Pixels with y down, as pick_particle projects; NaN for points behind the eye.
  const render::Mat4 matrix = camera.view_projection(static_cast<double>(width) / height);
  std::vector<Point> pixel(positions.size());
  for (std::size_t p = 0; p < positions.size(); ++p) {
    const Vec3& q = positions[p];
    const auto row = [&](int r) { return matrix(r, 0) * q.x + matrix(r, 1) * q.y + matrix(r, 2) * q.z + matrix(r, 3); };
    const double w = row(3);
    if (!(w > 0.0)) {
      pixel[p] = {std::numeric_limits<double>::quiet_NaN(), 0.0};
      continue;
    }
    pixel[p] = {(row(0) / w + 1.0) / 2.0 * width, (1.0 - row(1) / w) / 2.0 * height};
  }
  return connectors_crossed(model, pixel, {x0, y0}, {x1, y1});
}

std::vector<std::uint32_t> connectors_crossed_in_lattice(const ClothModel& model, const std::array<double, 2>& from,
                                                         const std::array<double, 2>& to) {
  std::vector<Point> lattice(model.particle_count());
  const auto cols = static_cast<std::size_t>(std::max(model.cols, 1));
  for (std::size_t p = 0; p < lattice.size(); ++p) {
    lattice[p] = {static_cast<double>(p / cols), static_cast<double>(p % cols)};
  }
  return connectors_crossed(model, lattice, from, to);
}

}  // namespace clothsim::viewer
