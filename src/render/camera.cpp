// Orbit camera math; conventions in camera.h.
#include "render/camera.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace clothsim::render {

Mat4 Mat4::identity() {
  Mat4 result;
  for (int i = 0; i < 4; ++i) result(i, i) = 1.0;
  return result;
}

std::array<float, 16> Mat4::to_float() const {
  std::array<float, 16> result{};
  for (std::size_t i = 0; i < 16; ++i) result[i] = static_cast<float>(m[i]);
  return result;
}

Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 result;
  for (int row = 0; row < 4; ++row) {
    for (int column = 0; column < 4; ++column) {
      double sum = 0.0;
      for (int k = 0; k < 4; ++k) sum += a(row, k) * b(k, column);
      result(row, column) = sum;
    }
  }
  return result;
}

namespace {

std::array<double, 4> transform(const Mat4& matrix, const Vec3& p) {
  std::array<double, 4> result{};
  for (int row = 0; row < 4; ++row) {
    result[static_cast<std::size_t>(row)] =
        matrix(row, 0) * p.x + matrix(row, 1) * p.y + matrix(row, 2) * p.z + matrix(row, 3);
  }
  return result;
}

Vec3 normalized(const Vec3& v) { return v / norm(v); }

}  // namespace

Vec3 transform_point(const Mat4& matrix, const Vec3& p) {
  const std::array<double, 4> h = transform(matrix, p);
  return Vec3{h[0], h[1], h[2]} / h[3];
}

Vec3 Camera::eye() const { return target - distance * forward(); }

Vec3 Camera::forward() const {
  const double el = std::clamp(elevation, -kMaxElevation, kMaxElevation);
  // The eye sits at target + distance (sin az cos el, sin el, cos az cos el); forward points back.
  return Vec3{-std::sin(azimuth) * std::cos(el), -std::sin(el), -std::cos(azimuth) * std::cos(el)};
}

Vec3 Camera::right() const { return Vec3{std::cos(azimuth), 0.0, -std::sin(azimuth)}; }

Vec3 Camera::up() const { return cross(right(), forward()); }

// Depth precision goes with far/near; 1e4 keeps 24-bit depth fine for sheets seen from outside.
// The near plane follows the distance so zooming in does not cut the sheet open.
double Camera::near_plane() const { return distance / 100.0; }
double Camera::far_plane() const { return distance * 100.0; }

Mat4 Camera::view() const {
  const Vec3 f = forward();
  const Vec3 r = right();
  const Vec3 u = up();
  const Vec3 e = eye();
  Mat4 result = Mat4::identity();
  // Rows are the eye frame's axes (right, up, -forward); the last column moves the eye to 0.
  const Vec3 axes[3] = {r, u, -f};
  for (int row = 0; row < 3; ++row) {
    const Vec3& axis = axes[row];
    result(row, 0) = axis.x;
    result(row, 1) = axis.y;
    result(row, 2) = axis.z;
    result(row, 3) = -dot(axis, e);
  }
  return result;
}

Mat4 Camera::projection(double aspect) const {
  // gluPerspective.
  const double f = 1.0 / std::tan(field_of_view / 2.0);
  const double n = near_plane();
  const double far = far_plane();
  Mat4 result;
  result(0, 0) = f / aspect;
  result(1, 1) = f;
  result(2, 2) = (far + n) / (n - far);
  result(2, 3) = 2.0 * far * n / (n - far);
  result(3, 2) = -1.0;
  return result;
}

void Camera::orbit(double delta_azimuth, double delta_elevation) {
  azimuth = std::remainder(azimuth + delta_azimuth, 2.0 * 3.14159265358979323846);
  elevation = std::clamp(elevation + delta_elevation, -kMaxElevation, kMaxElevation);
}

void Camera::pan(double right_fraction, double up_fraction) {
  // Visible height at the target's depth.
  const double height = 2.0 * distance * std::tan(field_of_view / 2.0);
  target += (-right_fraction * height) * right() + (-up_fraction * height) * up();
}

void Camera::zoom(double factor) {
  if (!(factor > 0.0) || !std::isfinite(factor)) return;
  distance = std::clamp(distance * factor, 1e-4, 1e6);
}

double Camera::framing_distance(double radius, double aspect) const {
  // A sphere of radius r at distance d subtends a half-angle asin(r / d); it fits when that is
  // at most the smaller of the vertical and horizontal half-fields.
  const double half_vertical = field_of_view / 2.0;
  const double half_horizontal = std::atan(std::tan(half_vertical) * aspect);
  const double half_angle = std::min(half_vertical, half_horizontal);
  return radius / std::sin(half_angle);
}

void Camera::frame_sphere(const Vec3& centre, double radius, double aspect) {
  target = centre;
  distance = std::clamp(framing_distance(std::max(radius, 1e-6), aspect), 1e-4, 1e6);
}

void Camera::frame(std::span<const Vec3> points, double aspect, double margin) {
  const double inf = std::numeric_limits<double>::infinity();
  Vec3 low{inf, inf, inf};
  Vec3 high{-inf, -inf, -inf};
  bool any = false;
  for (const Vec3& p : points) {
    if (!is_finite(p)) continue;
    any = true;
    low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
    high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
  }
  if (!any) return;
  const Vec3 centre = 0.5 * (low + high);
  double radius_squared = 0.0;
  for (const Vec3& p : points) {
    if (is_finite(p)) radius_squared = std::max(radius_squared, squared_norm(p - centre));
  }
  frame_sphere(centre, margin * std::sqrt(radius_squared), aspect);
}

double Camera::fitting_distance(std::span<const Vec3> points, double aspect, double margin) const {
  const Vec3 f = forward();
  const Vec3 r = right();
  const Vec3 u = up();
  const double tan_vertical = std::tan(field_of_view / 2.0) / margin;
  const double tan_horizontal = tan_vertical * aspect;
  // A point at offset q from the target has depth d + q.f in front of the eye, and lies in the
  // view when |q.r| <= tan_horizontal * depth and |q.u| <= tan_vertical * depth. The near plane
  // (distance / 100) must stay in front of it too: d + q.f >= d / 100 + a little.
  double needed = 0.0;
  for (const Vec3& p : points) {
    if (!is_finite(p)) continue;
    const Vec3 q = p - target;
    const double along = dot(q, f);
    needed = std::max({needed, std::abs(dot(q, r)) / tan_horizontal - along, std::abs(dot(q, u)) / tan_vertical - along,
                       -1.02 * along / 0.99});
  }
  return needed;
}

void Camera::fit(std::span<const Vec3> points, double aspect, double margin) {
  const double inf = std::numeric_limits<double>::infinity();
  Vec3 low{inf, inf, inf};
  Vec3 high{-inf, -inf, -inf};
  for (const Vec3& p : points) {
    if (!is_finite(p)) continue;
    low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
    high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
  }
  if (!(low.x <= high.x)) return;
  target = 0.5 * (low + high);
  distance = std::clamp(std::max(fitting_distance(points, aspect, margin), 1e-6), 1e-4, 1e6);
}

Projection Camera::project(const Vec3& point, int width, int height) const {
  const double aspect = static_cast<double>(width) / height;
  const std::array<double, 4> clip = transform(view_projection(aspect), point);
  Projection result;
  if (!(clip[3] > 0.0)) return result;
  const double x = clip[0] / clip[3];
  const double y = clip[1] / clip[3];
  result.depth = clip[2] / clip[3];
  result.x = (x + 1.0) / 2.0 * width;
  result.y = (1.0 - y) / 2.0 * height;
  result.visible = std::abs(x) <= 1.0 && std::abs(y) <= 1.0 && std::abs(result.depth) <= 1.0;
  return result;
}

Ray Camera::pick_ray(double x, double y, int width, int height) const {
  const double aspect = static_cast<double>(width) / height;
  const double ndc_x = 2.0 * x / width - 1.0;
  const double ndc_y = 1.0 - 2.0 * y / height;
  const double tan_half = std::tan(field_of_view / 2.0);
  const Vec3 direction = forward() + (ndc_x * tan_half * aspect) * right() + (ndc_y * tan_half) * up();
  return Ray{eye(), normalized(direction)};
}

long pick_nearest_point(const Ray& ray, std::span<const Vec3> points, double max_distance) {
  long best = -1;
  double best_offset = max_distance;
  double best_depth = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 relative = points[i] - ray.origin;
    const double depth = dot(relative, ray.direction);
    if (!(depth > 0.0)) continue;
    const double offset = norm(relative - depth * ray.direction);
    if (offset > max_distance) continue;
    // Points within 1% of the best offset count as a tie, so the nearer one wins.
    const bool clearly_closer = offset < best_offset * 0.99;
    const bool tie_nearer = offset <= best_offset * 1.01 && depth < best_depth;
    if (best < 0 || clearly_closer || tie_nearer) {
      best = static_cast<long>(i);
      best_offset = offset;
      best_depth = depth;
    }
  }
  return best;
}

}  // namespace clothsim::render
