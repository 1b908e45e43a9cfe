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

std::optional<SphereHit> pick_sphere(const render::Camera& camera, const ClothModel& model, double time, double x,
                                     double y, int width, int height) {
  const render::Ray ray = camera.pick_ray(x, y, width, height);  // unit direction
  std::optional<SphereHit> nearest;
  for (std::size_t c = 0; c < model.colliders.size(); ++c) {
    const Collider& sphere = model.colliders[c];
    if (sphere.shape != ColliderShape::sphere) continue;
    // |origin + t d - centre| = r: t^2 + 2 b t + q = 0 with b = (origin - centre).d.
    const Vec3 from_centre = ray.origin - (sphere.center + collider_offset(sphere, time));
    const double b = dot(from_centre, ray.direction);
    const double q = dot(from_centre, from_centre) - sphere.radius * sphere.radius;
    const double discriminant = b * b - q;
    if (q <= 0.0 || discriminant < 0.0) continue;  // the eye inside it, or a miss
    const double entry = -b - std::sqrt(discriminant);
    if (entry <= 0.0) continue;  // behind the eye
    if (!nearest || entry < nearest->distance) nearest = SphereHit{c, entry};
  }
  return nearest;
}

Vec3 place_beside_sheet(const render::Camera& camera, std::span<const Vec3> positions, double radius) {
  Vec3 low{}, high{};
  bool any = false;
  for (const Vec3& p : positions) {
    if (!is_finite(p)) continue;
    low = any ? Vec3{std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)} : p;
    high = any ? Vec3{std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)} : p;
    any = true;
  }
  // Beyond the box's bounding sphere by half a radius, whatever the direction of `right`.
  const double clearance = 0.5 * norm(high - low) + 1.5 * radius;
  return 0.5 * (low + high) + clearance * camera.right();
}

std::vector<std::uint32_t> connectors_crossed_on_screen(const render::Camera& camera, const ClothModel& model,
                                                        std::span<const Vec3> positions, double x0, double y0,
                                                        double x1, double y1, int width, int height) {
  // Pixels with y down, as pick_particle projects; NaN for points behind the eye.
  const render::Mat4 matrix = camera.view_projection(static_cast<double>(width) / height);
  std::vector<std::array<double, 2>> pixel(positions.size());
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

}  // namespace clothsim::viewer
