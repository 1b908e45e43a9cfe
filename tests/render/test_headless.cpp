// Headless rendering of a real simulated sheet, checked by what a person would look for in the
// picture, with tolerances (never byte for byte: drivers differ in rasterisation details):
//   - the sheet covers a plausible share of the image;
//   - it is shaded: the luminance over pixels of one side spreads (not one flat colour);
//   - on a folded sheet both the front and the back colour show, told apart by hue;
//   - the anchor marker shows at the anchor's projected position, even in the paper's
//     cell-centre mesh mode, which has no vertex there;
//   - overlays draw in their colours; the image size and orientation (top row first) are right;
//   - a torn sheet shows a gap along its tear, also when the tear comes after a first picture.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "model/model_edits.h"
#include "render/headless.h"
#include "render/image.h"
#include "render/renderer.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene/scene_model.h"
#include "sim/simulation.h"

namespace clothsim::render {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 480;
constexpr int kHeight = 320;

std::string scratch_path(const std::string& name) {
  const fs::path directory = fs::path(CLOTHSIM_TEST_TMPDIR) / "render";
  fs::create_directories(directory);
  return (directory / name).string();
}

// paper-fig5 (11 x 11, held at the centre) after `seconds` of simulated time.
struct FoldedSheet {
  ClothModel model;
  std::vector<Vec3> position;
};

FoldedSheet simulate_fig5(double seconds) {
  const SceneSpec spec = builtin_scene("paper-fig5");
  ClothModel model = build_model(spec);
  ClothState initial = build_initial_state(model, spec);
  SimulationSettings settings;
  settings.integrator = spec.integrator;
  settings.threads = 1;
  Simulation simulation(model, std::move(initial), settings);
  EXPECT_TRUE(simulation.advance_to(seconds));
  return {std::move(model), simulation.state().position};
}

const FoldedSheet& fig5() {
  static const FoldedSheet sheet = simulate_fig5(2.5);
  return sheet;
}

struct Hsv {
  double hue = 0.0;         // degrees [0, 360)
  double saturation = 0.0;  // [0, 1]
  double value = 0.0;       // [0, 1]
};

Hsv to_hsv(double r, double g, double b) {
  const double high = std::max({r, g, b});
  const double low = std::min({r, g, b});
  Hsv hsv;
  hsv.value = high;
  hsv.saturation = high > 0.0 ? (high - low) / high : 0.0;
  if (high == low) return hsv;
  double hue = 0.0;
  if (high == r) {
    hue = 60.0 * std::fmod((g - b) / (high - low), 6.0);
  } else if (high == g) {
    hue = 60.0 * ((b - r) / (high - low) + 2.0);
  } else {
    hue = 60.0 * ((r - g) / (high - low) + 4.0);
  }
  hsv.hue = hue < 0.0 ? hue + 360.0 : hue;
  return hsv;
}

Hsv to_hsv(const Colour& colour) { return to_hsv(colour.r, colour.g, colour.b); }
Hsv pixel_hsv(const Image& image, int x, int y) {
  const std::uint8_t* p = image.pixel(x, y);
  return to_hsv(p[0] / 255.0, p[1] / 255.0, p[2] / 255.0);
}

double hue_distance(double a, double b) {
  const double d = std::abs(a - b);
  return std::min(d, 360.0 - d);
}

// A saturated pixel whose hue is within 25 degrees of `colour`'s.
bool matches_hue(const Hsv& pixel, const Colour& colour) {
  return pixel.saturation > 0.25 && pixel.value > 0.08 && hue_distance(pixel.hue, to_hsv(colour).hue) < 25.0;
}

double luminance(const std::uint8_t* p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

struct Rendering {
  Image image;
  Camera camera;
};

Rendering render(const ClothModel& model, const std::vector<Vec3>& position, const RenderOptions& options,
                 const Camera* camera = nullptr, const std::string& png = {}) {
  HeadlessContext context(kWidth, kHeight);
  Renderer renderer;
  Rendering result;
  if (camera != nullptr) {
    result.camera = *camera;
  } else {
    result.camera.azimuth = 0.7;
    result.camera.elevation = 0.45;
    result.camera.fit(position, static_cast<double>(kWidth) / kHeight);
  }
  context.bind();
  renderer.draw(model, position, options, result.camera, kWidth, kHeight);
  context.read(result.image);
  if (!png.empty()) write_png(scratch_path(png), result.image);
  return result;
}

struct SheetPixels {
  int front = 0;
  int back = 0;
  std::vector<double> luminance;
};

SheetPixels classify(const Image& image, const RenderOptions& options) {
  SheetPixels pixels;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const Hsv hsv = pixel_hsv(image, x, y);
      const bool front = matches_hue(hsv, options.front_colour);
      const bool back = matches_hue(hsv, options.back_colour);
      if (front) ++pixels.front;
      if (back) ++pixels.back;
      if (front || back) pixels.luminance.push_back(luminance(image.pixel(x, y)));
    }
  }
  return pixels;
}

TEST(Headless, ContextDescribesItselfAndHasTheRequestedSize) {
  HeadlessContext context(64, 48);
  EXPECT_EQ(context.width(), 64);
  EXPECT_EQ(context.height(), 48);
  EXPECT_GE(context.samples(), 1);
  const std::string description = context.description();
  EXPECT_NE(description.find("OpenGL"), std::string::npos) << description;
  std::printf("headless context: %s\n", description.c_str());
}

// Anchor-coloured pixels within `radius` pixels of where `point` projects.
int marker_pixels_near(const Rendering& rendering, const Vec3& point, const Colour& colour, int radius = 12) {
  const Projection at = rendering.camera.project(point, kWidth, kHeight);
  EXPECT_TRUE(at.visible);
  int count = 0;
  const Image& image = rendering.image;
  for (int y = std::max(0, static_cast<int>(at.y) - radius); y < std::min(kHeight, static_cast<int>(at.y) + radius);
       ++y) {
    for (int x = std::max(0, static_cast<int>(at.x) - radius); x < std::min(kWidth, static_cast<int>(at.x) + radius);
         ++x) {
      if (matches_hue(pixel_hsv(image, x, y), colour)) ++count;
    }
  }
  return count;
}

int pixels_of_hue(const Image& image, const Colour& colour) {
  int count = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) count += matches_hue(pixel_hsv(image, x, y), colour) ? 1 : 0;
  }
  return count;
}

// The paper's Figure 5 sheet, 2.5 s after release: a tent hanging from its centre. With the eye
// a little below the rim (a third of the tent's height), the near faces show their top (front)
// and the far faces their underside (back) below them.
TEST(Headless, FoldedSheetShowsBothSidesWithItsAnchor) {
  const FoldedSheet& sheet = fig5();
  RenderOptions options;
  double lowest = sheet.position[0].y;
  double highest = lowest;
  for (const Vec3& p : sheet.position) {
    lowest = std::min(lowest, p.y);
    highest = std::max(highest, p.y);
  }
  ASSERT_GT(highest - lowest, 0.5) << "the sheet hangs";
  const double eye_height = lowest - 0.35 * (highest - lowest);
  Camera camera;
  camera.azimuth = 0.3;
  camera.elevation = 0.0;
  for (int iteration = 0; iteration < 4; ++iteration) {  // fit() moves the target and distance
    camera.fit(sheet.position, static_cast<double>(kWidth) / kHeight);
    camera.elevation = std::asin((eye_height - camera.target.y) / camera.distance);
  }
  camera.fit(sheet.position, static_cast<double>(kWidth) / kHeight);
  const Rendering rendering = render(sheet.model, sheet.position, options, &camera, "fig5_folded.png");
  const Image& image = rendering.image;
  ASSERT_EQ(image.width, kWidth);
  ASSERT_EQ(image.height, kHeight);

  const SheetPixels pixels = classify(image, options);
  const double total = static_cast<double>(kWidth) * kHeight;
  const double coverage = static_cast<double>(pixels.front + pixels.back) / total;
  // Seen nearly edge-on, the tent is a band across the image.
  EXPECT_GT(coverage, 0.05) << "front " << pixels.front << ", back " << pixels.back;
  EXPECT_LT(coverage, 0.90);
  EXPECT_GT(pixels.front, 0.015 * total);
  EXPECT_GT(pixels.back, 0.015 * total);

  ASSERT_EQ(sheet.model.anchor_count(), 1u);
  const Vec3 anchor = sheet.position[sheet.model.anchors[0].particle];
  EXPECT_GT(marker_pixels_near(rendering, anchor, options.anchor_colour), 40);
}

// Shading: over the pixels of one side (one base colour), brightness varies with the surface's
// orientation to the lights: the 10th and 90th luminance percentiles lie well apart.
TEST(Headless, SheetFillsTheViewAndOneSideIsShadedNotFlat) {
  const FoldedSheet& sheet = fig5();
  RenderOptions options;
  const Rendering rendering = render(sheet.model, sheet.position, options, nullptr, "fig5_above.png");
  // Framed from above at an angle: the sheet covers a good part of the image, not all of it.
  const SheetPixels pixels = classify(rendering.image, options);
  const double coverage = static_cast<double>(pixels.front + pixels.back) / (kWidth * kHeight);
  EXPECT_GT(coverage, 0.15);
  EXPECT_LT(coverage, 0.90);
  std::vector<double> luma;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      if (matches_hue(pixel_hsv(rendering.image, x, y), options.front_colour)) {
        luma.push_back(luminance(rendering.image.pixel(x, y)));
      }
    }
  }
  ASSERT_GT(luma.size(), static_cast<std::size_t>(kWidth * kHeight / 10));
  std::sort(luma.begin(), luma.end());
  const double low = luma[luma.size() / 10];
  const double high = luma[luma.size() * 9 / 10];
  EXPECT_GT(high - low, 12.0) << "10th percentile " << low << ", 90th " << high;
}

// Front is the side the rest normal (+y) points to: a flat sheet is all front colour from
// above and all back colour from below, whatever the mesh mode.
TEST(Headless, FrontFromAboveBackFromBelow) {
  const SceneSpec spec = builtin_scene("paper-fig5");
  const ClothModel model = build_model(spec);
  for (const SheetMeshMode mode : {SheetMeshMode::particles, SheetMeshMode::cell_centres}) {
    RenderOptions options;
    options.mesh_mode = mode;
    for (const double elevation : {0.8, -0.8}) {
      Camera camera;
      camera.elevation = elevation;
      camera.fit(model.particle_rest_position, static_cast<double>(kWidth) / kHeight);
      const Image image = render(model, model.particle_rest_position, options, &camera).image;
      const int front = pixels_of_hue(image, options.front_colour);
      const int back = pixels_of_hue(image, options.back_colour);
      const int wanted = elevation > 0 ? front : back;
      const int unwanted = elevation > 0 ? back : front;
      EXPECT_GT(wanted, kWidth * kHeight / 10) << "elevation " << elevation;
      EXPECT_EQ(unwanted, 0) << "elevation " << elevation;
    }
  }
}

// The paper's mesh mode has no vertex at the anchored centre particle, yet the marker shows
// there; its sheet covers fewer pixels (half a cell less on every side).
TEST(Headless, CellCentreModeShowsTheAnchorAndASmallerSheet) {
  const FoldedSheet& sheet = fig5();
  Camera camera;
  camera.azimuth = 0.3;
  camera.elevation = 1.2;
  camera.fit(sheet.position, static_cast<double>(kWidth) / kHeight);
  RenderOptions particles;
  RenderOptions cells;
  cells.mesh_mode = SheetMeshMode::cell_centres;
  const Rendering by_particles = render(sheet.model, sheet.position, particles, &camera);
  const Rendering by_cells = render(sheet.model, sheet.position, cells, &camera, "fig5_cell_centres.png");
  const int sheet_particles = pixels_of_hue(by_particles.image, particles.front_colour);
  const int sheet_cells = pixels_of_hue(by_cells.image, cells.front_colour);
  // 10 x 10 cells against 11 x 11 particles: the area ratio is about (9/10)^2 = 0.81.
  EXPECT_LT(sheet_cells, 0.92 * sheet_particles);
  EXPECT_GT(sheet_cells, 0.65 * sheet_particles);
  const Vec3 anchor = sheet.position[sheet.model.anchors[0].particle];
  EXPECT_GT(marker_pixels_near(by_cells, anchor, cells.anchor_colour), 40);
}

// A sheet torn across between rows 4 and 5, its lower part moved 2 spacings away: seen from
// above, the gap between the parts is background, where the intact sheet drawn just before by
// the same renderer (same grid, so only the break tells it to upload new triangles) spans it.
TEST(Headless, TornSheetShowsAGapAlongItsTear) {
  const SceneSpec spec = builtin_scene("paper-fig5");  // 11 x 11
  ClothModel model = build_model(spec);
  const double spacing = model.spacing;
  std::vector<Vec3> position = model.particle_rest_position;
  for (std::size_t p = 5 * 11; p < position.size(); ++p) position[p].z += 2.0 * spacing;
  Camera camera;
  camera.elevation = 1.5;
  camera.fit(position, static_cast<double>(kWidth) / kHeight);
  // The middle of the gap: half a spacing beyond row 4 each half of a broken connector reaches.
  const Vec3 gap{0.5 * spacing, 0.0, position[4 * 11].z + 1.5 * spacing};
  const Projection at = camera.project(gap, kWidth, kHeight);
  ASSERT_TRUE(at.visible);
  const RenderOptions options;
  const auto front_near_gap = [&](const Image& image) {
    int front = 0;
    for (int dy = -2; dy <= 2; ++dy) {
      for (int dx = -2; dx <= 2; ++dx) {
        const int x = static_cast<int>(at.x) + dx;
        const int y = static_cast<int>(at.y) + dy;
        front += matches_hue(pixel_hsv(image, x, y), options.front_colour) ? 1 : 0;
      }
    }
    return front;
  };

  HeadlessContext context(kWidth, kHeight);
  Renderer renderer;
  context.bind();
  Image intact;
  renderer.draw(model, position, options, camera, kWidth, kHeight);
  context.read(intact);
  for (std::uint32_t e = 0; e < model.connector_count(); ++e) {
    const auto [a, b] = model.connector_particles[e];
    if (a / 11 == 4 && b == a + 11) break_connector(model, e);
  }
  ASSERT_EQ(model.broken_connector_count, 11u);
  Image torn;
  renderer.draw(model, position, options, camera, kWidth, kHeight);
  context.read(torn);
  write_png(scratch_path("torn_sheet.png"), torn);
  EXPECT_EQ(front_near_gap(intact), 25) << "the intact sheet is stretched across the gap";
  EXPECT_EQ(front_near_gap(torn), 0) << "the torn sheet leaves the gap open";
  // Both parts are still drawn in full.
  EXPECT_GT(pixels_of_hue(torn, options.front_colour), kWidth * kHeight / 10);
}

// Overlays draw in their own colours when enabled, and not at all otherwise.
TEST(Headless, OverlaysAppearOnlyWhenEnabled) {
  const FoldedSheet& sheet = fig5();
  RenderOptions plain;
  plain.show_ground = false;
  RenderOptions springs = plain;
  springs.show_radials = true;
  springs.radial_colour = {0.1f, 0.9f, 0.9f};  // cyan: a hue nothing else has
  RenderOptions wire = plain;
  wire.show_wireframe = true;
  wire.wireframe_colour = {0.6f, 0.1f, 0.9f};  // violet
  RenderOptions connectors = plain;
  connectors.show_connectors = true;
  connectors.connector_colour = {0.1f, 0.8f, 0.1f};  // green
  const Image none = render(sheet.model, sheet.position, plain).image;
  const Image with_radials = render(sheet.model, sheet.position, springs, nullptr, "fig5_radials.png").image;
  const Image with_wire = render(sheet.model, sheet.position, wire, nullptr, "fig5_wireframe.png").image;
  const Image with_connectors = render(sheet.model, sheet.position, connectors, nullptr, "fig5_connectors.png").image;
  EXPECT_EQ(pixels_of_hue(none, springs.radial_colour), 0);
  EXPECT_EQ(pixels_of_hue(none, wire.wireframe_colour), 0);
  EXPECT_EQ(pixels_of_hue(none, connectors.connector_colour), 0);
  EXPECT_GT(pixels_of_hue(with_radials, springs.radial_colour), 500);
  EXPECT_GT(pixels_of_hue(with_wire, wire.wireframe_colour), 500);
  EXPECT_GT(pixels_of_hue(with_connectors, connectors.connector_colour), 500);
}

// A highlighted particle (the viewer's picked one) gets a marker of its own colour there.
TEST(Headless, HighlightedParticleIsMarked) {
  const FoldedSheet& sheet = fig5();
  RenderOptions options;
  options.highlighted_particle = 0;  // a corner
  Camera camera;
  camera.elevation = 1.0;
  camera.fit(sheet.position, static_cast<double>(kWidth) / kHeight);
  const Rendering rendering = render(sheet.model, sheet.position, options, &camera);
  EXPECT_GT(marker_pixels_near(rendering, sheet.position[0], options.highlight_colour), 40);
  EXPECT_EQ(marker_pixels_near(rendering, sheet.position[120], options.highlight_colour), 0);
}

}  // namespace
}  // namespace clothsim::render

namespace clothsim::render {
namespace {

// Colliders (issue 8): a sphere collider shows in its colour at its projection, where its path
// puts it at the frame's time (a moving one moves), and not at all with show_colliders off.
TEST(Headless, SphereColliderAppearsWhereItsPathPutsIt) {
  SceneSpec spec;
  spec.lattice.rows = 5;
  spec.lattice.cols = 5;
  spec.lattice.spacing = 0.1;
  ClothModel model = build_model(spec);
  const std::vector<Vec3> position = model.particle_rest_position;  // flat, 0.4 m square at y = 0
  Collider sphere;
  sphere.shape = ColliderShape::sphere;
  sphere.center = {0.0, -0.5, 0.0};
  sphere.radius = 0.15;
  sphere.path.kind = AnchorPathKind::linear;
  sphere.path.velocity = {0.7, 0.0, -0.7};  // at t = 1 s, 1 m away to the side
  model.colliders.push_back(sphere);
  const Vec3 start = sphere.center;
  const Vec3 moved = sphere.center + sphere.path.velocity;

  Camera camera;
  camera.azimuth = 0.7;
  camera.elevation = 0.45;
  std::vector<Vec3> framed = position;
  for (const Vec3& centre : {start, moved}) {
    for (const Vec3& offset : {Vec3{0.2, 0.2, 0.2}, Vec3{-0.2, -0.2, -0.2}}) framed.push_back(centre + offset);
  }
  camera.fit(framed, static_cast<double>(kWidth) / kHeight);
  const Projection at_start = camera.project(start, kWidth, kHeight);
  const Projection at_moved = camera.project(moved, kWidth, kHeight);
  ASSERT_TRUE(at_start.visible && at_moved.visible);
  ASSERT_GT(std::hypot(at_start.x - at_moved.x, at_start.y - at_moved.y), 40.0) << "the motion shows on screen";

  RenderOptions options;
  options.collider_colour = {0.15f, 0.75f, 0.25f};  // a saturated green, to find it by hue
  options.show_ground = false;
  const auto collider_pixels_near = [&](const Image& image, const Projection& at) {
    int count = 0;
    for (int dy = -3; dy <= 3; ++dy) {
      for (int dx = -3; dx <= 3; ++dx) {
        const Hsv pixel = pixel_hsv(image, static_cast<int>(at.x) + dx, static_cast<int>(at.y) + dy);
        count += matches_hue(pixel, options.collider_colour) ? 1 : 0;
      }
    }
    return count;
  };
  HeadlessContext context(kWidth, kHeight);
  Renderer renderer;
  context.bind();
  Image at_zero, at_one, hidden;
  renderer.draw(model, position, options, camera, kWidth, kHeight, 0.0);
  context.read(at_zero);
  renderer.draw(model, position, options, camera, kWidth, kHeight, 1.0);
  context.read(at_one);
  options.show_colliders = false;
  renderer.draw(model, position, options, camera, kWidth, kHeight, 0.0);
  context.read(hidden);
  write_png(scratch_path("sphere_collider.png"), at_zero);
  EXPECT_EQ(collider_pixels_near(at_zero, at_start), 49);
  EXPECT_EQ(collider_pixels_near(at_zero, at_moved), 0);
  EXPECT_EQ(collider_pixels_near(at_one, at_start), 0);
  EXPECT_EQ(collider_pixels_near(at_one, at_moved), 49);
  EXPECT_EQ(collider_pixels_near(hidden, at_start), 0);
}

}  // namespace
}  // namespace clothsim::render
