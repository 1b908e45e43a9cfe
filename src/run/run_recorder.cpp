// The headless recorder of a run's pictures (run_recorder.h).
#include "run/run_recorder.h"

#include "core/error.h"
#include "core/timer.h"
#include "run/render_plan_detail.h"

#if CLOTHSIM_HAVE_RENDER
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "render/image.h"
#include "render/render_error.h"
#include "render/video_writer.h"
#endif

namespace clothsim {

#if CLOTHSIM_HAVE_RENDER

// Frames are rendered on a worker thread, so that the simulation of the next frames and the
// rendering of this one overlap (docs/performance.md: paper-fig4 went from 126 s to 110 s on a
// busy 2-core machine with llvmpipe; with a GPU or more cores the overlap is larger). The main
// thread copies each frame's positions into a bounded queue (kQueueDepth frames; it waits when the
// renderer falls behind, so memory stays bounded) and the worker, which owns the OpenGL context
// while it runs, renders, reads back and pipes each frame to ffmpeg in order. A worker failure
// (ffmpeg died, disk full) is rethrown on the main thread at its next frame() or finish().
//
// Each frame is drawn with the model as it was at that frame: the frame holds a shared copy of
// the model, taken anew when the model's revision has moved since the last copy (a tear, a
// release, a cut, a collider added), so a sheet that never changes is copied once.
struct RunRecorder::Impl {
  static constexpr std::size_t kQueueDepth = 3;

  struct Frame {
    std::shared_ptr<const ClothModel> model;
    std::vector<Vec3> position;
    double time = 0.0;
  };

  std::shared_ptr<const RenderPlan> plan;
  // The model as of the last frame queued: a copy, the worker must not depend on the caller's
  // lifetimes or see a change the simulation makes while it draws.
  std::shared_ptr<const ClothModel> model;
  std::optional<FrameRenderer> renderer;
  std::optional<render::VideoWriter> video;
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
    renderer->draw(*frame.model, frame.position, frame.time);
    if (video) video->write_frame(renderer->image());
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
        frame.model.reset();
        std::lock_guard lock(mutex);
        spare.push_back(std::move(frame));
      }
    } catch (...) {
      std::lock_guard lock(mutex);
      failure = std::current_exception();
    }
    renderer->release();
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
      renderer->bind();  // back on this thread: finish() and the destructors use it
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
  } catch (const OutputError&) {
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
  if (impl.plan->video && !render::VideoWriter::available()) {
    throw OutputError(
        "cannot make animation.mp4: the ffmpeg program was not found or does not run (install ffmpeg, or use "
        "--render image for final.png only, or --render none)");
  }
  impl.renderer.emplace(impl.plan);
  impl.description = impl.renderer->description();
  impl.model = std::make_shared<const ClothModel>(model);
}

RunRecorder::~RunRecorder() = default;

void RunRecorder::begin(const std::filesystem::path& folder, int fps) {
  Impl& impl = *impl_;
  impl.fps = fps;
  if (!impl.renderer) return;
  try {
    if (impl.plan->video) {
      impl.video.emplace((folder / kVideoFile).string(), impl.plan->width, impl.plan->height, fps);
    }
  } catch (...) {
    rethrow_as_output_error();
  }
  impl.renderer->release();
  impl.worker = std::thread([&impl] { impl.run_worker(); });
}

void RunRecorder::frame(const ClothModel& model, std::span<const Vec3> position, double time) {
  Impl& impl = *impl_;
  if (!impl.renderer) return;
  // Copied before waiting for room in the queue: the worker never reads `impl.model`.
  if (impl.model->revision != model.revision) impl.model = std::make_shared<const ClothModel>(model);
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
  frame.model = impl.model;
  frame.position.assign(position.begin(), position.end());
  frame.time = time;
  impl.queue.push_back(std::move(frame));
  lock.unlock();
  impl.changed.notify_all();
}

void RunRecorder::finish(RunWriter& writer) {
  Impl& impl = *impl_;
  if (!impl.renderer) return;
  impl.stop_worker();
  const Stopwatch watch;
  const std::filesystem::path& folder = writer.partial();
  try {
    if (impl.failure) std::rethrow_exception(impl.failure);
    if (impl.plan->image && impl.frames > 0) render::write_png((folder / kImageFile).string(), impl.renderer->image());
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

bool RunRecorder::active() const { return impl_->renderer.has_value(); }
std::string RunRecorder::description() const { return impl_->description; }
double RunRecorder::seconds() const { return impl_->seconds; }
long RunRecorder::frames() const { return impl_->frames; }

#else  // without the render module: render "none" is all there is

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

}  // namespace clothsim
