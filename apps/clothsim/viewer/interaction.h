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

// Intact connectors whose projection on a width x height view crosses the pixel segment from
// (x0, y0) to (x1, y1) (connectors with an end behind the eye are skipped).
std::vector<std::uint32_t> connectors_crossed_on_screen(const render::Camera& camera, const ClothModel& model,
                                                        std::span<const Vec3> positions, double x0, double y0,
                                                        double x1, double y1, int width, int height);

}  // namespace clothsim::viewer
