#include "viewer/interaction.h"

#include <cmath>

namespace clothsim::viewer {

long pick_particle(const render::Camera& camera, std::span<const Vec3> positions, double x, double y, int width,
                   int height, double radius) {
  long best = -1;
  double best_distance = radius;
  double best_depth = 0.0;
  for (std::size_t p = 0; p < positions.size(); ++p) {
    const render::Projection projection = camera.project(positions[p], width, height);
    if (!projection.visible) continue;
    const double distance = std::hypot(projection.x - x, projection.y - y);
    if (distance > radius) continue;
    // Within a tenth of a pixel counts as the same distance: then the nearer particle wins.
    const bool closer = distance < best_distance - 0.1;
    const bool tie_nearer = distance <= best_distance + 0.1 && projection.depth < best_depth;
    if (best < 0 || closer || tie_nearer) {
      best = static_cast<long>(p);
      best_distance = distance;
      best_depth = projection.depth;
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

}  // namespace clothsim::viewer
