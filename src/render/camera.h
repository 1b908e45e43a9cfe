// An orbit camera: the eye moves on a sphere around a target point.
//
// State: target (m), azimuth and elevation (rad), distance from the target (m) and the vertical
// field of view (rad). Y is up (the simulation's convention). Azimuth 0 looks from +z towards -z
// (the eye sits at target + distance (sin az cos el, sin el, cos az cos el)); elevation is
// clamped just short of +-90 degrees so the view never degenerates (the up vector stays +y).
//
// One type serves the headless renderer (a fixed or framing camera) and the interactive viewer
// (orbit, pan, zoom, picking), so that both show the same picture for the same settings.
// Matrices follow OpenGL: right-handed eye space looking down -z, clip space z in [-w, w],
// column-major storage (Mat4::m[column * 4 + row]) so they upload with glUniformMatrix4fv
// unchanged. Near and far planes are derived from the distance, so zooming never clips the
// sheet (near = distance / 100, far = distance * 100).
//
// Rejected: a free-fly (first-person) camera. Looking at one object from all sides is what an
// orbit camera does best, and it cannot lose the object.
#pragma once

#include <array>
#include <span>

#include "core/vec3.h"

namespace clothsim::render {

// 4x4 matrix, column-major (OpenGL's layout): m[column * 4 + row].
struct Mat4 {
  std::array<double, 16> m{};

  static Mat4 identity();
  double operator()(int row, int column) const { return m[static_cast<std::size_t>(column * 4 + row)]; }
  double& operator()(int row, int column) { return m[static_cast<std::size_t>(column * 4 + row)]; }
  // The matrix as floats, for glUniformMatrix4fv(location, 1, GL_FALSE, ...).
  std::array<float, 16> to_float() const;
};

Mat4 operator*(const Mat4& a, const Mat4& b);
// Transforms the point (p, 1) and divides by w.
Vec3 transform_point(const Mat4& matrix, const Vec3& p);

// A ray origin + t direction, t >= 0; direction is unit length.
struct Ray {
  Vec3 origin;
  Vec3 direction;
};

// Where a point lands on the image: pixel coordinates with (0, 0) the top-left corner of the
// top-left pixel, x right, y down (the convention of images and window mouse events), and the
// NDC depth in [-1, 1]. visible is false behind the eye or outside the view volume.
struct Projection {
  double x = 0.0;
  double y = 0.0;
  double depth = 0.0;
  bool visible = false;
};

struct Camera {
  Vec3 target{0.0, 0.0, 0.0};     // point looked at and orbited, m
  double azimuth = 0.6;           // rad, rotation about +y; 0 looks along -z
  double elevation = 0.5;         // rad, above the horizontal plane; clamped to +-kMaxElevation
  double distance = 10.0;         // eye to target, m (> 0)
  double field_of_view = 0.7854;  // vertical, rad (45 degrees)

  static constexpr double kMaxElevation = 1.55;  // rad, just under pi/2

  Vec3 eye() const;      // eye position, m
  Vec3 forward() const;  // unit vector from the eye to the target
  Vec3 right() const;    // unit, horizontal, to the right of the view
  Vec3 up() const;       // unit, the image's up direction (right x forward ... orthonormal)
  double near_plane() const;
  double far_plane() const;

  Mat4 view() const;                     // world -> eye
  Mat4 projection(double aspect) const;  // eye -> clip; aspect = width / height
  Mat4 view_projection(double aspect) const { return projection(aspect) * view(); }

  // Interaction (the viewer maps mouse motion onto these).
  void orbit(double delta_azimuth, double delta_elevation);  // rad; elevation clamped
  // Moves the target (and eye) in the view plane so that the picture at the target's depth moves
  // right by `right_fraction` and up by `up_fraction` screen heights (drag-to-pan: pass the
  // mouse motion divided by the window height, with y flipped).
  void pan(double right_fraction, double up_fraction);
  // Multiplies the distance by `factor` (> 0): < 1 zooms in. Distance stays in [1e-4, 1e6] m.
  void zoom(double factor);

  // Sets target and distance so that the bounding sphere of `points` (centre at the box centre,
  // radius to the farthest point, times `margin`) fits the view at `aspect` (width / height) in
  // both directions, keeping the current azimuth, elevation and field of view. Non-finite points
  // are ignored; with none left the camera is unchanged.
  void frame(std::span<const Vec3> points, double aspect, double margin = 1.1);
  // Tighter than frame(): centres the target on the bounding box of `points` and sets the
  // smallest distance at which every point projects inside the view (shrunk by `margin`) from
  // the current direction. Depends on the direction, so a view that orbits should use frame().
  void fit(std::span<const Vec3> points, double aspect, double margin = 1.05);
  // The smallest distance at which every point of `points` projects inside the view (shrunk by
  // `margin`) from the current target and direction; 0 with no finite points.
  double fitting_distance(std::span<const Vec3> points, double aspect, double margin = 1.05) const;
  // The same for a given sphere.
  void frame_sphere(const Vec3& centre, double radius, double aspect);
  // Distance at which a sphere of `radius` just fits a view of `aspect`.
  double framing_distance(double radius, double aspect) const;

  // Pixel position of `point` in a width x height image (see Projection).
  Projection project(const Vec3& point, int width, int height) const;
  // The ray from the eye through pixel position (x, y) (same convention; pixel centres at +0.5).
  Ray pick_ray(double x, double y, int width, int height) const;
};

// Index of the point of `points` nearest to `ray` (perpendicular distance), among points in front
// of the eye within `max_distance` (m) of the ray; -1 if none. Ties go to the point nearer the eye.
long pick_nearest_point(const Ray& ray, std::span<const Vec3> points, double max_distance);

}  // namespace clothsim::render
