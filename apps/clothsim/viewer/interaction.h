// Mouse picking and dragging in the viewer, as geometry on the renderer's Camera.
//
// Picking works in pixels, not metres: the particle whose projection is nearest to the cursor,
// within a radius of a few pixels, so a particle is as easy to hit far away as close up (a
// metric radius around the pick ray would shrink to nothing on screen when zoomed out). Among
// particles at the same pixel distance (a sheet seen edge-on) the one nearer the eye wins.
// A grabbed particle moves on the plane through its position at the grab that faces the camera,
// so it stays under the cursor and keeps its depth.
//
// Cutting works in pixels too: a cut is a segment on the screen (one motion of the cursor while
// the cut modifier is held), and it breaks every intact connector whose projected segment it
// crosses, whatever the depth, as a knife drawn across the picture would. Testing in 2D against
// the projections needs no ray casting against a moving, folded sheet, and a cut across a folded
// sheet goes through every layer under it, which is what a cut through a fold does. Scripts cut
// the same way in rest-lattice coordinates instead (model/lattice_cuts.h, which scenes use for
// their initial cuts too), so that a test does not depend on the camera.
//
// Spheres are picked in metres instead: the first sphere the ray through the cursor enters, as
// a sphere has a visible extent of its own. A grabbed sphere moves, like a particle, on the plane
// through its centre (at the grab) that faces the camera, keeping the offset between its centre
// and the point grabbed, so it does not jump to put its centre under the cursor.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/vec3.h"
#include "model/cloth_model.h"
#include "model/lattice_cuts.h"
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

// A sphere collider under the cursor.
struct SphereHit {
  std::size_t collider = 0;  // index in model.colliders
  double distance = 0.0;     // m, from the eye along the pick ray to where the ray enters the sphere
};

// The sphere (of model.colliders, where they are at `time`) that the ray through pixel (x, y)
// enters first in front of the eye; none if it enters none (an eye inside a sphere picks not that one).
std::optional<SphereHit> pick_sphere(const render::Camera& camera, const ClothModel& model, double time, double x,
                                     double y, int width, int height);

// Where a new sphere of `radius` (m) starts: clear of the sheet's bounding box, on the camera's
// right of it at the height of its centre, so it is in view and touches nothing until dragged.
Vec3 place_beside_sheet(const render::Camera& camera, std::span<const Vec3> positions, double radius);

// Intact connectors whose projection on a width x height view crosses the pixel segment from
// (x0, y0) to (x1, y1) (connectors with an end behind the eye are skipped).
std::vector<std::uint32_t> connectors_crossed_on_screen(const render::Camera& camera, const ClothModel& model,
                                                        std::span<const Vec3> positions, double x0, double y0,
                                                        double x1, double y1, int width, int height);

}  // namespace clothsim::viewer
