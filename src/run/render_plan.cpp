// The picture settings of a run, their memory, and the headless frame renderer (render_plan.h).
#include "run/render_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "model/sheet_mesh.h"
#include "run/render_plan_detail.h"
#include "run/run_writer.h"

#if CLOTHSIM_HAVE_RENDER
#include "render/headless.h"
#include "render/image.h"
#include "render/renderer.h"
#endif

namespace clothsim {
namespace {

[[maybe_unused]] constexpr double kDegree = 3.14159265358979323846 / 180.0;

// Parses a whole string as a double; false on trailing text, empty input or non-finite values.
[[maybe_unused]] bool parse_double(const std::string& text, double& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(value);
}

bool parse_int(const std::string& text, int& value) {
  if (text.empty() || text.size() > 6 || text.find_first_not_of("0123456789") != std::string::npos) return false;
  value = std::stoi(text);
  return true;
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = text.find(separator, start);
    parts.push_back(text.substr(start, end - start));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return parts;
}

}  // namespace

const char* default_render_choice() {
#if CLOTHSIM_HAVE_RENDER
  return "all";
#else
  return "none";
#endif
}

std::string render_flags_json(const RenderFlags& flags) {
  return nlohmann::json{{"render", flags.render}, {"size", flags.size}, {"camera", flags.camera},
                        {"mesh", flags.mesh},     {"show", flags.show}, {"samples", flags.samples}}
      .dump();
}

RenderFlags render_flags_from_json(std::string_view text) {
  RenderFlags flags;
  const nlohmann::json json = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  const auto take = [&json](std::string& field, const char* key) {
    if (json.is_object() && json.contains(key) && json[key].is_string()) field = json[key].get<std::string>();
  };
  take(flags.render, "render");
  take(flags.size, "size");
  take(flags.camera, "camera");
  take(flags.mesh, "mesh");
  take(flags.show, "show");
  take(flags.samples, "samples");
  return flags;
}

std::shared_ptr<const RenderPlan> parse_render_flags(const RenderFlags& flags) {
  auto plan = std::make_shared<RenderPlan>();
  if (flags.render == "all") {
    plan->image = plan->video = true;
  } else if (flags.render == "image") {
    plan->image = true;
  } else if (flags.render == "video") {
    plan->video = true;
  } else if (flags.render != "none") {
    throw InputError("--render", "", "must be all, image, video or none, got \"" + flags.render + "\"");
  }
#if !CLOTHSIM_HAVE_RENDER
  if (plan->image || plan->video) {
    throw InputError("--render", "",
                     "this clothsim was built without rendering (CLOTHSIM_BUILD_RENDER=OFF); only --render none is "
                     "available");
  }
#endif

  const std::vector<std::string> sides = split(flags.size, 'x');
  int width = 0;
  int height = 0;
  if (sides.size() != 2 || !parse_int(sides[0], width) || !parse_int(sides[1], height) || width < kMinPictureSide ||
      width > kMaxPictureSide || height < kMinPictureSide || height > kMaxPictureSide) {
    throw InputError("--size", "",
                     "expects WIDTHxHEIGHT in pixels, each in [" + std::to_string(kMinPictureSide) + ", " +
                         std::to_string(kMaxPictureSide) + "], got \"" + flags.size + "\"");
  }
  plan->width = width;
  plan->height = height;
  int samples = 0;
  if (!parse_int(flags.samples, samples) || samples < 1 || samples > 16) {
    throw InputError("--samples", "", "expects an integer in [1, 16], got \"" + flags.samples + "\"");
  }
  plan->samples = samples;

#if CLOTHSIM_HAVE_RENDER
  render::CameraChoice& camera = plan->camera;
  if (flags.camera == "auto") {
    camera.mode = render::CameraMode::automatic;
  } else if (flags.camera == "follow") {
    camera.mode = render::CameraMode::follow;
  } else {
    const std::vector<std::string> parts = split(flags.camera, ',');
    double azimuth = 0.0;
    double elevation = 0.0;
    double distance = 0.0;
    const bool numbers = (parts.size() == 2 || parts.size() == 3) && parse_double(parts[0], azimuth) &&
                         parse_double(parts[1], elevation) && (parts.size() == 2 || parse_double(parts[2], distance));
    if (!numbers || std::abs(elevation) > 89.0 || (parts.size() == 3 && !(distance > 0.0))) {
      throw InputError("--camera", "",
                       "expects auto, follow or AZIMUTH,ELEVATION[,DISTANCE] (degrees, elevation in [-89, 89]; "
                       "distance in m, > 0), got \"" +
                           flags.camera + "\"");
    }
    camera.azimuth = azimuth * kDegree;
    camera.elevation = elevation * kDegree;
    if (parts.size() == 3) {
      camera.mode = render::CameraMode::fixed;
      camera.distance = distance;
    }
  }

  if (flags.mesh == "particles") {
    plan->options.mesh_mode = SheetMeshMode::particles;
  } else if (flags.mesh == "cell-centres" || flags.mesh == "cell-centers") {
    plan->options.mesh_mode = SheetMeshMode::cell_centres;
  } else {
    throw InputError("--mesh", "", "must be particles or cell-centres, got \"" + flags.mesh + "\"");
  }

  if (!flags.show.empty()) {
    for (const std::string& item : split(flags.show, ',')) {
      if (item == "connectors") {
        plan->options.show_connectors = true;
      } else if (item == "radials") {
        plan->options.show_radials = true;
      } else if (item == "wireframe") {
        plan->options.show_wireframe = true;
      } else if (item == "no-ground") {
        plan->options.show_ground = false;
      } else if (item == "no-anchors") {
        plan->options.show_anchors = false;
      } else if (item == "no-colliders") {
        plan->options.show_colliders = false;
      } else {
        throw InputError("--show", "",
                         "expects a comma-separated list of connectors, radials, wireframe, no-ground, no-anchors, "
                         "no-colliders; "
                         "got \"" +
                             item + "\"");
      }
    }
  }
#else
  if (flags.camera != "auto" || flags.mesh != "particles" || !flags.show.empty()) {
    throw InputError("--camera", "", "this clothsim was built without rendering (CLOTHSIM_BUILD_RENDER=OFF)");
  }
#endif
  return plan;
}

std::size_t picture_bytes(int width, int height, int samples, const LatticeCounts& counts) {
  // The graphics stack and its threads: 88 MiB measured on Debian 12's Mesa 22.3 with llvmpipe
  // (a 21 x 21 run with pictures, less its framebuffers, against one without).
  constexpr std::size_t kGraphicsStackBytes = std::size_t{88} << 20;
  // The driver's copies of the vertex and index buffers: the rest of the 1250 bytes per
  // particle that pictures cost at 256 x 256 and 512 x 512 (llvmpipe).
  constexpr std::size_t kDriverBytesPerParticle = 420;
  const std::size_t pixels =
      static_cast<std::size_t>(std::max(width, 0)) * static_cast<std::size_t>(std::max(height, 0));
  // Multisampled colour and depth, the resolved colour, the image read back (RGB).
  const std::size_t framebuffers = pixels * (static_cast<std::size_t>(std::max(samples, 1)) * 8 + 4 + 3);
  return kGraphicsStackBytes + framebuffers + SheetMesh::bytes_for(counts.rows, counts.cols) +
         counts.particles * (6 * sizeof(float) + kDriverBytesPerParticle);
}

std::size_t estimate_render_bytes(const RenderPlan& plan, const LatticeCounts& counts, std::size_t anchors,
                                  bool model_changes) {
  if (!plan.image && !plan.video) return 0;
  // Besides drawing: the frames queued and recycled (RunRecorder's queue of 3, one being drawn,
  // one spare; run/run_recorder.cpp), and the model copied for the rendering thread, once, or
  // for each frame held when the model changes during the run.
  constexpr std::size_t kFramesHeld = 3 + 2;
  const std::size_t models = model_changes ? kFramesHeld : 1;
  return picture_bytes(plan.width, plan.height, plan.samples, counts) +
         models * lattice_model_bytes(counts, anchors) + counts.particles * kFramesHeld * sizeof(Vec3);
}

std::string describe_render_outputs(const RenderPlan& plan) {
  std::string text;
  if (plan.image) text += kImageFile;
  if (plan.video) {
    if (!text.empty()) text += " and ";
    text += kVideoFile;
  }
  return text;
}

#if CLOTHSIM_HAVE_RENDER

struct FrameRenderer::Impl {
  std::shared_ptr<const RenderPlan> plan;
  std::optional<render::HeadlessContext> context;
  std::optional<render::Renderer> renderer;  // needs the context current, from construction to destruction
  std::optional<render::CameraDirector> director;
  render::RenderOptions options;
  render::Image image;  // the last frame drawn

  ~Impl() {
    if (!context) return;
    try {
      context->bind();  // the renderer's destructor deletes GL objects of this context
    } catch (...) {
      // The objects die with the context.
    }
    renderer.reset();
  }
};

namespace {

// Render failures are output errors; the message keeps the renderer's advice.
[[noreturn]] void rethrow_render_error() {
  try {
    throw;
  } catch (const render::RenderError& error) {
    throw OutputError(error.what());
  }
}

}  // namespace

FrameRenderer::FrameRenderer(std::shared_ptr<const RenderPlan> plan) : impl_(std::make_unique<Impl>()) {
  Impl& impl = *impl_;
  impl.plan = std::move(plan);
  try {
    impl.context.emplace(impl.plan->width, impl.plan->height, impl.plan->samples);
    impl.renderer.emplace();
  } catch (...) {
    rethrow_render_error();
  }
  impl.options = impl.plan->options;
  impl.director.emplace(impl.plan->camera, static_cast<double>(impl.plan->width) / impl.plan->height);
}

FrameRenderer::~FrameRenderer() = default;

void FrameRenderer::draw(const ClothModel& model, std::span<const Vec3> position, double time) {
  Impl& impl = *impl_;
  try {
    impl.director->update(model, position, time);
    impl.options.ground_height = impl.director->ground_height();
    impl.context->bind();
    impl.renderer->draw(model, position, impl.options, impl.director->camera(), impl.plan->width, impl.plan->height,
                        time);
    impl.context->read(impl.image);
  } catch (...) {
    rethrow_render_error();
  }
}

const render::Image& FrameRenderer::image() const { return impl_->image; }

void FrameRenderer::bind() {
  try {
    impl_->context->bind();
  } catch (...) {
    rethrow_render_error();
  }
}

void FrameRenderer::release() { impl_->context->release(); }

std::string FrameRenderer::description() const {
  return std::to_string(impl_->plan->width) + "x" + std::to_string(impl_->plan->height) + ", " +
         impl_->context->description();
}

#else  // without the render module there is nothing to draw with

struct FrameRenderer::Impl {};
FrameRenderer::FrameRenderer(std::shared_ptr<const RenderPlan> /*plan*/) {
  throw OutputError("this clothsim was built without rendering (CLOTHSIM_BUILD_RENDER=OFF)");
}
FrameRenderer::~FrameRenderer() = default;
void FrameRenderer::draw(const ClothModel& /*model*/, std::span<const Vec3> /*position*/, double /*time*/) {}
const render::Image& FrameRenderer::image() const { throw OutputError("no pictures in this build"); }
void FrameRenderer::bind() {}
void FrameRenderer::release() {}
std::string FrameRenderer::description() const { return {}; }

#endif

}  // namespace clothsim
