#include "viewer/viewer_window.h"

#include <epoxy/gl.h>
// After epoxy: GLFW must not pull in a GL header of its own.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "core/timer.h"
#include "io/npy.h"
#include "io/run_writer.h"
#include "render/image.h"
#include "render/renderer.h"
#include "viewer/frame_pacer.h"
#include "viewer/interaction.h"
#include "viewer/panel.h"

namespace clothsim::viewer {
namespace {

constexpr double kPickRadius = 12.0;       // pixels around the cursor that pick a particle
constexpr double kOrbitPerPixel = 0.008;   // rad of orbit per pixel of mouse motion
constexpr double kOrbitPerKey = 0.06;      // rad per key press (or repeat)
constexpr double kPanPerKey = 0.05;        // fraction of the view height per key press
constexpr double kZoomPerNotch = 0.9;      // distance factor per scroll notch or key press

std::string g_glfw_error;  // the last GLFW error, for messages

void on_glfw_error(int /*code*/, const char* description) { g_glfw_error = description; }

// glfwInit/glfwTerminate for a scope.
class GlfwLibrary {
 public:
  GlfwLibrary() {
    glfwSetErrorCallback(on_glfw_error);
    if (glfwInit() != GLFW_TRUE) {
      throw render::RenderError("cannot open a window: " + g_glfw_error +
                                ". 'clothsim view' needs a display (DISPLAY set); on a machine without one, "
                                "run it under a virtual X server: xvfb-run -a clothsim view ...");
    }
  }
  ~GlfwLibrary() { glfwTerminate(); }
  GlfwLibrary(const GlfwLibrary&) = delete;
  GlfwLibrary& operator=(const GlfwLibrary&) = delete;
};

// The back buffer, read after the scene is drawn (without the panel), rows top first.
render::Image read_back_buffer(int width, int height) {
  render::Image image;
  image.width = width;
  image.height = height;
  const std::size_t row_bytes = static_cast<std::size_t>(width) * 3;
  std::vector<std::uint8_t> bottom_up(row_bytes * static_cast<std::size_t>(height));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, bottom_up.data());
  image.rgb.resize(bottom_up.size());
  for (int y = 0; y < height; ++y) {
    std::copy_n(&bottom_up[static_cast<std::size_t>(height - 1 - y) * row_bytes], row_bytes,
                &image.rgb[static_cast<std::size_t>(y) * row_bytes]);
  }
  return image;
}

class Viewer {
 public:
  Viewer(Session& session, const ViewerOptions& options);
  ~Viewer();
  Viewer(const Viewer&) = delete;
  Viewer& operator=(const Viewer&) = delete;

  int run();

 private:
  enum class MouseMode { none, orbit, pan, drag, cut };

  static Viewer& of(GLFWwindow* window) { return *static_cast<Viewer*>(glfwGetWindowUserPointer(window)); }
  static void on_mouse_button(GLFWwindow* window, int button, int action, int mods);
  static void on_cursor(GLFWwindow* window, double x, double y);
  static void on_scroll(GLFWwindow* window, double x, double y);
  static void on_key(GLFWwindow* window, int key, int scancode, int action, int mods);
  static void on_char(GLFWwindow* window, unsigned int codepoint);

  void mouse_button(int button, int action, int mods);
  void cursor(double x, double y);
  void key(int key, int action, int mods);

  // Cursor position in framebuffer pixels.
  std::pair<double, double> cursor_pixels() const;
  // Re-frames the sheet and keeps it in view from now on (F, the Frame button, a reset).
  void frame_camera();
  // Grows the box of positions seen and, while keep_in_view_, frames it.
  void keep_sheet_in_view();
  // The grabbed particle follows the cursor over the next `duration` s of simulated time.
  void drag_grabbed(double duration);
  void release_grabbed();
  void take_screenshot(const std::string& path, bool scripted);
  std::string next_screenshot_path();
  void draw_scene();
  void draw_ui();

  Session& session_;
  ViewerOptions options_;
  GlfwLibrary glfw_;
  GLFWwindow* window_ = nullptr;
  std::unique_ptr<render::Renderer> renderer_;
  render::Camera camera_;
  struct SeenBox {
    Vec3 low, high;  // m, bounding box of the positions since the last frame_camera()
    bool any = false;
  } seen_;
  bool keep_in_view_ = true;  // frame seen_ every frame until the user pans or zooms
  render::RenderOptions render_options_;
  double ground_height_ = 0.0;  // m; only ever lowered, so the ground stays put
  FramePacer pacer_;
  PanelState panel_;
  int width_ = 0;  // framebuffer, pixels
  int height_ = 0;

  MouseMode mouse_mode_ = MouseMode::none;
  double press_x_ = 0.0;
  double press_y_ = 0.0;
  double last_x_ = 0.0;
  double last_y_ = 0.0;
  long grabbed_ = -1;
  Vec3 grab_plane_point_;
  long hovered_ = -1;
  std::size_t cut_count_ = 0;  // connectors broken by the current cut
  bool quit_ = false;
  std::uint64_t screenshot_count_ = 0;
};

// An OpenGL 3.3 core window with `samples` MSAA samples, its context current.
GLFWwindow* open_window(const ViewerOptions& options, const std::string& title, int samples) {
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, samples);
  GLFWwindow* window = glfwCreateWindow(options.width, options.height, title.c_str(), nullptr, nullptr);
  if (window == nullptr) throw render::RenderError("cannot open an OpenGL 3.3 core window: " + g_glfw_error);
  glfwMakeContextCurrent(window);
  return window;
}

// Mesa's software rasterisers, which the default of 4x MSAA would slow down about five times.
bool is_software_renderer() {
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const std::string name = renderer != nullptr ? renderer : "";
  return name.find("llvmpipe") != std::string::npos || name.find("softpipe") != std::string::npos ||
         name.find("swrast") != std::string::npos;
}

Viewer::Viewer(Session& session, const ViewerOptions& options) : session_(session), options_(options) {
  const std::string title = "clothsim view: " + session.scene().name;
  window_ = open_window(options, title, options.samples < 0 ? 4 : options.samples);
  if (options.samples < 0 && is_software_renderer()) {
    glfwDestroyWindow(window_);
    window_ = open_window(options, title, 0);
  }
  glfwSwapInterval(options.vsync && options.benchmark_frames == 0 ? 1 : 0);
  glfwSetWindowUserPointer(window_, this);
  glfwGetFramebufferSize(window_, &width_, &height_);

  renderer_ = std::make_unique<render::Renderer>();

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working folder
  ImGui::StyleColorsLight();
  // Our callbacks forward to ImGui's first (install_callbacks = false), then act on what ImGui
  // does not take.
  ImGui_ImplGlfw_InitForOpenGL(window_, false);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  glfwSetMouseButtonCallback(window_, on_mouse_button);
  glfwSetCursorPosCallback(window_, on_cursor);
  glfwSetScrollCallback(window_, on_scroll);
  glfwSetKeyCallback(window_, on_key);
  glfwSetCharCallback(window_, on_char);
  glfwSetCursorEnterCallback(window_, ImGui_ImplGlfw_CursorEnterCallback);
  glfwSetWindowFocusCallback(window_, ImGui_ImplGlfw_WindowFocusCallback);

  panel_.visible = options.show_panel;
  const std::span<const Vec3> positions = session_.simulation().state().position;
  ground_height_ = render::Renderer::automatic_ground_height(session_.simulation().model(), positions);
  frame_camera();
}

Viewer::~Viewer() {
  renderer_.reset();  // needs the context
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window_);
}

void Viewer::frame_camera() {
  seen_ = SeenBox{};
  keep_in_view_ = true;
  keep_sheet_in_view();
}

void Viewer::keep_sheet_in_view() {
  // Frame everything the sheet has covered since the last re-framing (F, the Frame button, a
  // reset), as `clothsim run --camera auto` does: the box only grows, so the view zooms out as the
  // sheet falls or swings wide and never pumps back and forth. The framing sphere does not depend
  // on the direction, so orbiting keeps it; panning or zooming by hand ends it until F.
  for (const Vec3& p : session_.simulation().state().position) {
    if (!is_finite(p)) continue;
    if (!seen_.any) seen_.low = seen_.high = p;
    seen_.low = {std::min(seen_.low.x, p.x), std::min(seen_.low.y, p.y), std::min(seen_.low.z, p.z)};
    seen_.high = {std::max(seen_.high.x, p.x), std::max(seen_.high.y, p.y), std::max(seen_.high.z, p.z)};
    seen_.any = true;
  }
  if (!keep_in_view_ || !seen_.any) return;
  // Fit the box into the part of the window the panel leaves free, then move the picture into
  // the middle of that part.
  const double panel = panel_.visible ? std::min(kPanelWidth + 16.0, 0.5 * width_) : 0.0;
  const double free_width = std::max(1.0, width_ - panel);
  const std::array<Vec3, 2> box{seen_.low, seen_.high};
  camera_.frame(box, free_width / std::max(1, height_), 1.2);
  camera_.pan(-0.5 * panel / std::max(1, height_), 0.0);
}

std::pair<double, double> Viewer::cursor_pixels() const {
  double x = 0.0;
  double y = 0.0;
  glfwGetCursorPos(window_, &x, &y);
  int window_width = 1;
  int window_height = 1;
  glfwGetWindowSize(window_, &window_width, &window_height);
  return {x * width_ / std::max(1, window_width), y * height_ / std::max(1, window_height)};
}

void Viewer::on_mouse_button(GLFWwindow* window, int button, int action, int mods) {
  ImGui_ImplGlfw_MouseButtonCallback(window, button, action, mods);
  of(window).mouse_button(button, action, mods);
}

void Viewer::on_cursor(GLFWwindow* window, double x, double y) { of(window).cursor(x, y); }

void Viewer::on_scroll(GLFWwindow* window, double x, double y) {
  ImGui_ImplGlfw_ScrollCallback(window, x, y);
  if (ImGui::GetIO().WantCaptureMouse) return;
  Viewer& viewer = of(window);
  viewer.camera_.zoom(std::pow(kZoomPerNotch, y));
  viewer.keep_in_view_ = false;
}

void Viewer::on_key(GLFWwindow* window, int key, int scancode, int action, int mods) {
  ImGui_ImplGlfw_KeyCallback(window, key, scancode, action, mods);
  of(window).key(key, action, mods);
}

void Viewer::on_char(GLFWwindow* window, unsigned int codepoint) { ImGui_ImplGlfw_CharCallback(window, codepoint); }

void Viewer::mouse_button(int button, int action, int mods) {
  const auto [x, y] = cursor_pixels();
  if (action == GLFW_RELEASE) {
    if (mouse_mode_ == MouseMode::drag) release_grabbed();
    mouse_mode_ = MouseMode::none;
    return;
  }
  if (ImGui::GetIO().WantCaptureMouse || mouse_mode_ != MouseMode::none) return;
  press_x_ = last_x_ = x;
  press_y_ = last_y_ = y;
  const std::span<const Vec3> positions = session_.simulation().state().position;
  const long picked = pick_particle(camera_, positions, x, y, width_, height_, kPickRadius);
  const bool shift = (mods & GLFW_MOD_SHIFT) != 0;
  if (picked >= 0 && (button == GLFW_MOUSE_BUTTON_RIGHT || (button == GLFW_MOUSE_BUTTON_LEFT && shift))) {
    // Pin or unpin by click.
    const auto particle = static_cast<std::uint32_t>(picked);
    if (session_.is_pinned(particle)) {
      session_.unpin(particle);
      panel_.status = "unpinned " + session_.simulation().model().describe_particle(particle);
    } else {
      session_.pin(particle);
      panel_.status = "pinned " + session_.simulation().model().describe_particle(particle);
    }
    return;
  }
  if (button == GLFW_MOUSE_BUTTON_LEFT && (mods & GLFW_MOD_CONTROL) != 0) {
    // The knife: every cursor motion until the release cuts what it crosses (see cursor()).
    mouse_mode_ = MouseMode::cut;
    cut_count_ = 0;
    return;
  }
  if (button == GLFW_MOUSE_BUTTON_LEFT && picked >= 0) {
    grabbed_ = picked;
    grab_plane_point_ = positions[static_cast<std::size_t>(picked)];
    mouse_mode_ = MouseMode::drag;
    return;
  }
  mouse_mode_ = button == GLFW_MOUSE_BUTTON_LEFT ? MouseMode::orbit : MouseMode::pan;
}

void Viewer::cursor(double /*window_x*/, double /*window_y*/) {
  const auto [x, y] = cursor_pixels();
  const double dx = x - last_x_;
  const double dy = y - last_y_;
  last_x_ = x;
  last_y_ = y;
  switch (mouse_mode_) {
    case MouseMode::orbit:
      camera_.orbit(-dx * kOrbitPerPixel, dy * kOrbitPerPixel);
      break;
    case MouseMode::pan:
      camera_.pan(dx / height_, -dy / height_);  // the picture follows the cursor
      keep_in_view_ = false;
      break;
    case MouseMode::cut: {
      // The segment the cursor just moved along, in pixels, against the connectors as drawn.
      const std::vector<std::uint32_t> crossed =
          connectors_crossed_on_screen(camera_, session_.simulation().model(), session_.simulation().state().position,
                                       x - dx, y - dy, x, y, width_, height_);
      if (!crossed.empty()) {
        cut_count_ += session_.cut(crossed);
        panel_.status = "cut " + std::to_string(cut_count_) + " connector" + (cut_count_ == 1 ? "" : "s");
      }
      break;
    }
    case MouseMode::drag:  // the target follows the cursor in drag_grabbed(), once per frame
    case MouseMode::none:
      break;
  }
}

void Viewer::key(int key, int action, int mods) {
  if (action == GLFW_RELEASE || ImGui::GetIO().WantCaptureKeyboard) return;
  const bool shift = (mods & GLFW_MOD_SHIFT) != 0;
  const bool repeat = action == GLFW_REPEAT;
  switch (key) {
    case GLFW_KEY_SPACE:
      if (!repeat) session_.set_playing(!session_.playing());
      break;
    case GLFW_KEY_N:
    case GLFW_KEY_PERIOD:
      session_.set_playing(false);
      panel_.step_requested = true;
      break;
    case GLFW_KEY_R:
      if (!repeat) panel_.reset_requested = true;
      break;
    case GLFW_KEY_S:
    case GLFW_KEY_F12:
      if (!repeat) panel_.screenshot_requested = true;
      break;
    case GLFW_KEY_F:
      frame_camera();
      break;
    case GLFW_KEY_H:
    case GLFW_KEY_TAB:
      if (!repeat) panel_.visible = !panel_.visible;
      break;
    case GLFW_KEY_LEFT:
      shift ? camera_.pan(-kPanPerKey, 0.0) : camera_.orbit(kOrbitPerKey, 0.0);
      if (shift) keep_in_view_ = false;
      break;
    case GLFW_KEY_RIGHT:
      shift ? camera_.pan(kPanPerKey, 0.0) : camera_.orbit(-kOrbitPerKey, 0.0);
      if (shift) keep_in_view_ = false;
      break;
    case GLFW_KEY_UP:
      shift ? camera_.pan(0.0, kPanPerKey) : camera_.orbit(0.0, kOrbitPerKey);
      if (shift) keep_in_view_ = false;
      break;
    case GLFW_KEY_DOWN:
      shift ? camera_.pan(0.0, -kPanPerKey) : camera_.orbit(0.0, -kOrbitPerKey);
      if (shift) keep_in_view_ = false;
      break;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD:
    case GLFW_KEY_PAGE_UP:
      camera_.zoom(kZoomPerNotch);
      keep_in_view_ = false;
      break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT:
    case GLFW_KEY_PAGE_DOWN:
      camera_.zoom(1.0 / kZoomPerNotch);
      keep_in_view_ = false;
      break;
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q:
      quit_ = true;
      break;
    default:
      break;
  }
}

void Viewer::drag_grabbed(double duration) {
  if (grabbed_ < 0) return;
  const auto [x, y] = cursor_pixels();
  const std::optional<Vec3> target = drag_target(camera_, grab_plane_point_, x, y, width_, height_);
  if (!target) return;
  session_.drag(static_cast<std::uint32_t>(grabbed_), *target, duration);
}

void Viewer::release_grabbed() {
  if (grabbed_ >= 0) session_.release(static_cast<std::uint32_t>(grabbed_));
  grabbed_ = -1;
}

std::string Viewer::next_screenshot_path() {
  std::string name;
  for (char c : session_.scene().name) {
    const bool safe = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
    name += safe ? c : '_';
  }
  char number[32];
  std::snprintf(number, sizeof number, "-%03llu.png", static_cast<unsigned long long>(++screenshot_count_));
  return options_.screenshot_folder + "/" + (name.empty() ? "clothsim" : name) + number;
}

void Viewer::take_screenshot(const std::string& path, bool scripted) {
  try {
    render::write_png(path, read_back_buffer(width_, height_));
  } catch (const std::runtime_error& error) {
    if (scripted) throw OutputError(std::string("screenshot: ") + error.what());
    panel_.status = std::string("screenshot failed: ") + error.what();
    std::fprintf(stderr, "clothsim: error: screenshot: %s\n", error.what());
    return;
  }
  panel_.status = "saved " + path;
  std::printf("screenshot: %s (%dx%d, t = %.4g s)\n", path.c_str(), width_, height_, session_.time());
  std::fflush(stdout);
}

void Viewer::draw_scene() {
  const Simulation& simulation = session_.simulation();
  ground_height_ = std::min(ground_height_,
                            render::Renderer::automatic_ground_height(simulation.model(), simulation.state().position));
  render_options_ = panel_.render;
  render_options_.ground_height = ground_height_;
  render_options_.highlighted_particle = grabbed_ >= 0 ? grabbed_ : hovered_;
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  renderer_->draw(simulation.model(), simulation.state().position, render_options_, camera_, width_, height_,
                  simulation.state().time);
}

void Viewer::draw_ui() {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  draw_panel(panel_, session_, pacer_);
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

int Viewer::run() {
  const bool scripted = options_.scripted();
  const double frame_time = 1.0 / session_.scene().output.fps;
  std::optional<ScriptPlayer> player;
  if (options_.script) player.emplace(*options_.script, frame_time);

  Stopwatch benchmark_clock;
  double benchmark_simulated = 0.0;
  double benchmark_simulation_seconds = 0.0;  // wall time spent in Session::advance
  std::vector<double> frame_intervals;
  double last_frame = glfwGetTime();
  bool reported_failure = false;

  for (std::uint64_t frame = 0;; ++frame) {
    glfwPollEvents();
    glfwGetFramebufferSize(window_, &width_, &height_);
    while ((width_ < 1 || height_ < 1) && glfwWindowShouldClose(window_) == 0) {  // minimised: wait
      glfwWaitEventsTimeout(0.1);
      glfwGetFramebufferSize(window_, &width_, &height_);
    }
    if (glfwWindowShouldClose(window_) != 0 || quit_) break;
    const double now = glfwGetTime();
    const double wall_interval = now - last_frame;
    last_frame = now;
    if (frame == 1) benchmark_clock.restart();

    if (panel_.reset_requested) {
      panel_.reset_requested = false;
      grabbed_ = -1;
      mouse_mode_ = MouseMode::none;
      session_.reset();
      frame_camera();
      reported_failure = false;
      panel_.status = "reset to t = 0";
    }

    // 1. Advance: a fixed frame of simulated time in a scripted run, the wall time since the last
    //    frame (within the work budget) otherwise; one frame for a single step while paused.
    if (frame > 0) {
      const bool step = !session_.playing() && panel_.step_requested;
      panel_.step_requested = false;
      const bool moving = session_.playing() || step;
      const double duration = scripted || step ? frame_time : FramePacer::simulated_step(wall_interval);
      if (step) session_.set_playing(true);  // for this frame, so that a drag drives rather than places
      if (mouse_mode_ == MouseMode::drag) drag_grabbed(moving ? duration : 0.0);
      double advanced = 0.0;
      const Stopwatch simulation_watch;
      if (moving) {
        advanced = scripted || step ? session_.advance(duration)
                                    : session_.advance(duration, FramePacer::kWorkBudget, FramePacer::kPiece);
      }
      if (step) session_.set_playing(false);
      pacer_.record(wall_interval, advanced, session_.playing());
      if (frame >= 2) {  // frame 1's interval holds the start-up: the benchmark starts after it
        benchmark_simulated += advanced;
        benchmark_simulation_seconds += simulation_watch.seconds();
        frame_intervals.push_back(wall_interval);
      }
    }
    if (session_.failed()) {
      session_.set_playing(false);
      if (!reported_failure) {
        std::fprintf(stderr, "clothsim: error: simulation failed %s\n", session_.simulation().failure()->message.c_str());
        reported_failure = true;
      }
    }

    // 2. This frame's scripted events, then the picture.
    std::vector<std::string> screenshots;
    if (player) {
      ScriptPlayer::FrameRequests requests = player->fire(frame, session_);
      screenshots = std::move(requests.screenshots);
      if (requests.quit) quit_ = true;
    }
    for (const auto& [at, path] : options_.screenshots) {
      if (at == frame) screenshots.push_back(path);
    }
    session_.record_energy();
    if (mouse_mode_ == MouseMode::none && !ImGui::GetIO().WantCaptureMouse) {
      const auto [x, y] = cursor_pixels();
      hovered_ = pick_particle(camera_, session_.simulation().state().position, x, y, width_, height_, kPickRadius);
    } else if (mouse_mode_ != MouseMode::drag) {
      hovered_ = -1;
    }

    keep_sheet_in_view();
    draw_scene();
    for (const std::string& path : screenshots) take_screenshot(path, true);
    if (panel_.screenshot_requested) {
      panel_.screenshot_requested = false;
      take_screenshot(next_screenshot_path(), false);
    }
    if (panel_.frame_requested) {
      panel_.frame_requested = false;
      frame_camera();
    }
    draw_ui();
    glfwSwapBuffers(window_);

    if (options_.frames > 0 && frame >= options_.frames) break;
    if (options_.benchmark_frames > 0 && frame >= options_.benchmark_frames + 1) break;
  }

  if (options_.benchmark_frames > 0 && !frame_intervals.empty()) {
    const double wall = benchmark_clock.seconds();
    std::vector<double> sorted = frame_intervals;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[sorted.size() / 2];
    const Simulation& simulation = session_.simulation();
    std::printf(
        "benchmark: %s, %dx%d lattice (%zu particles), %s, window %dx%d\n"
        "benchmark: %zu frames in %.3f s: %.1f fps (median frame %.2f ms); simulated %.3f s, %.3fx real time\n"
        "benchmark: per frame %.2f ms simulating, %.2f ms drawing, the panel and the rest\n",
        session_.scene().name.c_str(), simulation.model().rows, simulation.model().cols,
        simulation.model().particle_count(), std::string(to_string(simulation.settings().integrator.kind)).c_str(),
        width_, height_, frame_intervals.size(), wall, static_cast<double>(frame_intervals.size()) / wall,
        1e3 * median, benchmark_simulated, benchmark_simulated / wall,
        1e3 * benchmark_simulation_seconds / static_cast<double>(frame_intervals.size()),
        1e3 * (wall - benchmark_simulation_seconds) / static_cast<double>(frame_intervals.size()));
    std::fflush(stdout);
  }
  if (!options_.dump_state.empty()) {
    const std::vector<Vec3>& position = session_.simulation().state().position;
    std::vector<double> values;
    values.reserve(position.size() * 3);
    for (const Vec3& p : position) values.insert(values.end(), {p.x, p.y, p.z});
    const std::array<std::size_t, 2> shape = {position.size(), 3};
    try {
      write_npy(options_.dump_state, values, shape);
    } catch (const std::runtime_error& error) {
      throw OutputError(std::string("--dump-state: ") + error.what());
    }
  }
  return scripted && session_.failed() ? 1 : 0;
}

}  // namespace

int run_viewer(Session& session, const ViewerOptions& options) {
  Viewer viewer(session, options);
  return viewer.run();
}

}  // namespace clothsim::viewer
