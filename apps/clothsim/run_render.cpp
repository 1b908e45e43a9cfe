// The --render family of flags and the headless recorder of `clothsim run` (run_render.h).
#include "run_render.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "cli_support.h"
#include "core/error.h"
#include "core/timer.h"
#include "io/run_writer.h"
#include "memory_check.h"

#if CLOTHSIM_HAVE_RENDER
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "render/camera_director.h"
#include "render/headless.h"
#include "render/renderer.h"
#include "render/video_writer.h"
#endif

namespace clothsim::cli {

namespace {

constexpr int kMinSide = 16;
constexpr int kMaxSide = 8192;
[[maybe_unused]] constexpr double kDegree = 3.14159265358979323846 / 180.0;

#if CLOTHSIM_HAVE_RENDER
constexpr const char* kDefaultRender = "all";
#else
constexpr const char* kDefaultRender = "none";
#endif

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

struct RenderPlan {
  bool image = false;
  bool video = false;
  int width = 1280;
  int height = 720;
  int samples = 4;  // MSAA samples per pixel
#if CLOTHSIM_HAVE_RENDER
  render::CameraChoice camera;
  render::RenderOptions options;
#endif
};

void add_render_flags(CLI::App& app, RenderFlags& flags) {
  flags.render = kDefaultRender;
  flags.size = "1280x720";
  flags.camera = "auto";
  flags.mesh = "particles";
  app.add_option("--render", flags.render,
                 "pictures to write: all (final.png and animation.mp4), image, video or none (no OpenGL at all, "
                 "for batch runs)")
      ->type_name("WHAT")
      ->default_str(kDefaultRender)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.add_option("--size", flags.size,
                 "image and video size in pixels, each side in [" + std::to_string(kMinSide) + ", " +
                     std::to_string(kMaxSide) + "]")
      ->type_name("WxH")
      ->default_str("1280x720")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.add_option("--camera", flags.camera,
                 "auto (frame everything seen so far), follow (glide after the sheet), or AZIMUTH,ELEVATION[,DISTANCE] "
                 "in degrees and metres (auto framing from that direction; a distance fixes the camera)")
      ->type_name("MODE")
      ->default_str("auto")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.add_option("--mesh", flags.mesh,
                 "rendered mesh: particles (vertices at the masses) or cell-centres (the paper's: vertices at the "
                 "centres of 4 masses)")
      ->type_name("MODE")
      ->default_str("particles")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  flags.samples = "4";
  app.add_option("--samples", flags.samples,
                 "anti-aliasing samples per pixel (MSAA), an integer in [1, 16]; 1 turns it off (about 3x faster on "
                 "a software renderer)")
      ->type_name("N")
      ->default_str("4")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.add_option("--show", flags.show,
                 "overlays, comma-separated: connectors, radials, wireframe; and no-ground, no-anchors")
      ->type_name("LIST")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
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
  if (sides.size() != 2 || !parse_int(sides[0], width) || !parse_int(sides[1], height) || width < kMinSide ||
      width > kMaxSide || height < kMinSide || height > kMaxSide) {
    throw InputError("--size", "",
                     "expects WIDTHxHEIGHT in pixels, each in [" + std::to_string(kMinSide) + ", " +
                         std::to_string(kMaxSide) + "], got \"" + flags.size + "\"");
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

std::size_t estimate_render_bytes(const RenderPlan& plan, const LatticeCounts& counts, std::size_t anchors) {
  if (!plan.image && !plan.video) return 0;
  // Besides drawing (memory_check.h): the model copied for the rendering thread, and the frames
  // queued and recycled (RunRecorder::Impl::kQueueDepth, one being drawn, one spare).
  constexpr std::size_t kFramesHeld = 3 + 2;
  return picture_bytes(plan.width, plan.height, plan.samples, counts) + lattice_model_bytes(counts, anchors) +
         counts.particles * kFramesHeld * sizeof(Vec3);
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

// Frames are rendered on a worker thread, so that the simulation of the next frames and the
// rendering of this one overlap (docs/performance.md: paper-fig4 went from 126 s to 110 s on a
// busy 2-core machine with llvmpipe; with a GPU or more cores the overlap is larger). The main
// thread copies each frame's
// positions into a bounded queue (kQueueDepth frames; it waits when the renderer falls behind,
// so memory stays bounded) and the worker, which owns the OpenGL context while it runs, renders,
// reads back and pipes each frame to ffmpeg in order. A worker failure (ffmpeg died, disk full)
// is rethrown on the main thread at its next frame() or finish().
struct RunRecorder::Impl {
  static constexpr std::size_t kQueueDepth = 3;

  struct Frame {
    std::vector<Vec3> position;
    double time = 0.0;
  };

  std::shared_ptr<const RenderPlan> plan;
  ClothModel model;  // a copy: the worker must not depend on the caller's lifetimes
  std::optional<render::HeadlessContext> context;
  std::optional<render::Renderer> renderer;
  std::optional<render::VideoWriter> video;
  std::optional<render::CameraDirector> director;
  render::RenderOptions options;
  render::Image image;  // the last frame rendered
  double seconds = 0.0;
  long frames = 0;
  int fps = 0;
  std::string description;

  // Shared between the main thread and the worker, under `mutex`.
  std::mutex mutex;
  std::condition_variable changed;
  std::deque<Frame> queue;     // frames to render, oldest first
  std::vector<Frame> spare;    // recycled position buffers
  bool closing = false;        // no more frames will come
  std::exception_ptr failure;  // the worker's error, if any
  std::thread worker;

  void render_frame(const Frame& frame) {
    const Stopwatch watch;
    director->update(model, frame.position, frame.time);
    options.ground_height = director->ground_height();
    context->bind();
    renderer->draw(model, frame.position, options, director->camera(), plan->width, plan->height, frame.time);
    context->read(image);
    if (video) video->write_frame(image);
    ++frames;
    seconds += watch.seconds();
  }

  void run_worker() {
    try {
      while (true) {
        Frame frame;
        {
          std::unique_lock lock(mutex);
          changed.wait(lock, [this] { return !queue.empty() || closing; });
          if (queue.empty()) break;
          frame = std::move(queue.front());
          queue.pop_front();
        }
        changed.notify_all();
        render_frame(frame);
        std::lock_guard lock(mutex);
        spare.push_back(std::move(frame));
      }
    } catch (...) {
      std::lock_guard lock(mutex);
      failure = std::current_exception();
    }
    context->release();
    changed.notify_all();
  }

  // Stops the worker after the frames queued so far and takes the context back.
  void stop_worker() {
    if (!worker.joinable()) return;
    {
      std::lock_guard lock(mutex);
      closing = true;
    }
    changed.notify_all();
    worker.join();
    try {
      context->bind();  // back on this thread: finish() and the destructors use it
    } catch (...) {
      if (!failure) failure = std::current_exception();
    }
  }

  ~Impl() {
    // A run that ends by an exception: stop rendering (the frames still queued are dropped by
    // the worker when ffmpeg is killed, or rendered: either way nothing outlives this), and make
    // the context current here again for the renderer's destructor.
    if (worker.joinable()) {
      {
        std::lock_guard lock(mutex);
        queue.clear();
      }
      stop_worker();
    }
  }
};

namespace {

// Render failures are output errors (exit 3); the message keeps the renderer's advice.
[[noreturn]] void rethrow_as_output_error() {
  try {
    throw;
  } catch (const render::RenderError& error) {
    throw OutputError(error.what());
  } catch (const std::runtime_error& error) {
    throw OutputError(error.what());
  }
}

}  // namespace

RunRecorder::RunRecorder(std::shared_ptr<const RenderPlan> plan, const ClothModel& model)
    : impl_(std::make_unique<Impl>()) {
  Impl& impl = *impl_;
  impl.plan = std::move(plan);
  if (!impl.plan->image && !impl.plan->video) return;
  try {
    if (impl.plan->video && !render::VideoWriter::available()) {
      throw render::RenderError(
          "cannot make animation.mp4: the ffmpeg program was not found or does not run (install ffmpeg, or use "
          "--render image for final.png only, or --render none)");
    }
    impl.context.emplace(impl.plan->width, impl.plan->height, impl.plan->samples);
    impl.renderer.emplace();
    impl.description =
        std::to_string(impl.plan->width) + "x" + std::to_string(impl.plan->height) + ", " + impl.context->description();
  } catch (...) {
    rethrow_as_output_error();
  }
  impl.model = model;
  impl.options = impl.plan->options;
  impl.director.emplace(impl.plan->camera, static_cast<double>(impl.plan->width) / impl.plan->height);
}

RunRecorder::~RunRecorder() = default;

void RunRecorder::begin(const std::filesystem::path& folder, int fps) {
  Impl& impl = *impl_;
  impl.fps = fps;
  if (!impl.context) return;
  try {
    if (impl.plan->video) {
      impl.video.emplace((folder / kVideoFile).string(), impl.plan->width, impl.plan->height, fps);
    }
  } catch (...) {
    rethrow_as_output_error();
  }
  impl.context->release();
  impl.worker = std::thread([&impl] { impl.run_worker(); });
}

void RunRecorder::frame(const ClothModel& /*model*/, std::span<const Vec3> position, double time) {
  Impl& impl = *impl_;
  if (!impl.context) return;
  std::unique_lock lock(impl.mutex);
  impl.changed.wait(lock, [&impl] { return impl.queue.size() < Impl::kQueueDepth || impl.failure; });
  if (impl.failure) {
    try {
      std::rethrow_exception(impl.failure);
    } catch (...) {
      rethrow_as_output_error();
    }
  }
  Impl::Frame frame;
  if (!impl.spare.empty()) {
    frame = std::move(impl.spare.back());
    impl.spare.pop_back();
  }
  frame.position.assign(position.begin(), position.end());
  frame.time = time;
  impl.queue.push_back(std::move(frame));
  lock.unlock();
  impl.changed.notify_all();
}

void RunRecorder::finish(RunWriter& writer) {
  Impl& impl = *impl_;
  if (!impl.context) return;
  impl.stop_worker();
  const Stopwatch watch;
  const std::filesystem::path& folder = writer.partial();
  try {
    if (impl.failure) std::rethrow_exception(impl.failure);
    if (impl.plan->image && impl.frames > 0) render::write_png((folder / kImageFile).string(), impl.image);
    if (impl.video) impl.video->finish();
  } catch (...) {
    rethrow_as_output_error();
  }
  impl.seconds += watch.seconds();
  const int width = impl.plan->width;
  const int height = impl.plan->height;
  if (impl.plan->image && impl.frames > 0) {
    writer.add_file(std::string(kImageFile), {{"width", width}, {"height", height}, {"frame", impl.frames - 1}});
  }
  if (impl.video) {
    // yuv420p needs even sides: the video is padded by a pixel where the size is odd.
    writer.add_file(std::string(kVideoFile), {{"frames", impl.video->frames()},
                                              {"fps", impl.fps},
                                              {"width", width + width % 2},
                                              {"height", height + height % 2},
                                              {"codec", "h264"},
                                              {"pixel_format", "yuv420p"}});
  }
}

bool RunRecorder::active() const { return impl_->context.has_value(); }
std::string RunRecorder::description() const { return impl_->description; }
double RunRecorder::seconds() const { return impl_->seconds; }
long RunRecorder::frames() const { return impl_->frames; }

#else  // without the render module: --render none is all there is

struct RunRecorder::Impl {};
RunRecorder::RunRecorder(std::shared_ptr<const RenderPlan> /*plan*/, const ClothModel& /*model*/) {}
RunRecorder::~RunRecorder() = default;
void RunRecorder::begin(const std::filesystem::path& /*folder*/, int /*fps*/) {}
void RunRecorder::frame(const ClothModel& /*model*/, std::span<const Vec3> /*position*/, double /*time*/) {}
void RunRecorder::finish(RunWriter& /*writer*/) {}
bool RunRecorder::active() const { return false; }
std::string RunRecorder::description() const { return {}; }
double RunRecorder::seconds() const { return 0.0; }
long RunRecorder::frames() const { return 0; }

#endif

}  // namespace clothsim::cli
