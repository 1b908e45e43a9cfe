// Mouse picking and dragging in the viewer, as geometry on the renderer's Camera.
//
// Picking works in pixels, not metres: the particle whose projection is nearest to the cursor,
// within a radius of a few pixels, so a particle is as easy to hit far away as close up (a
// metric radius around the pick ray would shrink to nothing on screen when zoomed out). Among
// particles at the same pixel distance (a sheet seen edge-on) the one nearer the eye wins.
// A grabbed particle moves on the plane through its position at the grab that faces the camera,
// so it stays under the cursor and keeps its depth.
#pragma once

#include <optional>
#include <span>

#include "core/vec3.h"
#include "render/camera.h"

namespace clothsim::viewer {

// Index of the particle whose projection is nearest to pixel (x, y) of a width x height view,
// within `radius` pixels; -1 if none. Particles behind the eye are never picked.
long pick_particle(const render::Camera& camera, std::span<const Vec3> positions, double x, double y, int width,
                   int height, double radius);

// Where the ray through pixel (x, y) meets the plane through `plane_point` perpendicular to the
// camera's forward direction; none if the ray runs parallel to it or meets it behind the eye.
std::optional<Vec3> drag_target(const render::Camera& camera, const Vec3& plane_point, double x, double y, int width,
                                int height);

}  // namespace clothsim::viewer
