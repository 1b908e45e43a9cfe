// What the renderer draws and in which colours. Plain data with defaults, shared by `clothsim run`
// (headless images and video) and `clothsim view` (the window), so both show the same picture.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "model/sheet_mesh.h"

namespace clothsim::render {

// Linear RGB in [0, 1].
struct Colour {
  float r = 0.0f;
  float g = 0.0f;
  float b = 0.0f;
};

struct RenderOptions {
  // Where the mesh's vertices sit (model/sheet_mesh.h): at the particles, or the paper's
  // centres of 4 particles.
  SheetMeshMode mesh_mode = SheetMeshMode::particles;

  bool show_sheet = true;        // the shaded surface
  bool show_anchors = true;      // a marker at every anchored particle
  bool show_ground = true;       // a grid on a horizontal ground plane
  bool show_wireframe = false;   // the triangle edges over the surface
  bool show_connectors = false;  // connector springs as lines between particles
  bool show_radials = false;     // radial springs as a line between the midpoints of their two connectors
  bool show_colliders = true;    // the model's obstacles (model.colliders), shaded, where they are at the time

  // Height of the ground plane, m. Unset: a little below the lowest point drawn (set per frame
  // by the caller for a steady ground; see Renderer::draw).
  std::optional<double> ground_height;
  double ground_extent = 0.0;  // half-width of the grid square, m; 0 chooses from the sheet size

  // Marker radius, m; 0 chooses from the lattice spacing (0.45 L) and the view so a marker stays
  // a few pixels wide at any zoom.
  double anchor_radius = 0.0;

  // A particle to mark (e.g. under the mouse, or being dragged), or -1 for none.
  std::int64_t highlighted_particle = -1;

  Colour front_colour{0.85f, 0.33f, 0.18f};      // the side whose rest normal is +y: terracotta
  Colour back_colour{0.20f, 0.45f, 0.80f};       // the other side: blue
  Colour anchor_colour{1.00f, 0.85f, 0.10f};     // anchors: yellow, contrasting with both sides
  Colour highlight_colour{0.10f, 0.95f, 0.35f};  // highlighted particle: green
  Colour connector_colour{0.10f, 0.10f, 0.10f};
  Colour radial_colour{0.75f, 0.10f, 0.75f};
  Colour wireframe_colour{0.05f, 0.05f, 0.05f};
  Colour ground_colour{0.55f, 0.57f, 0.60f};
  // Obstacles: a warm neutral grey, lighter than the ground, apart from both sides of the sheet.
  Colour collider_colour{0.72f, 0.70f, 0.66f};
  Colour background_colour{0.93f, 0.94f, 0.96f};
};

}  // namespace clothsim::render
