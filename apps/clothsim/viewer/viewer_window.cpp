#include "viewer/viewer_window.h"

#include "core/error.h"

#include <epoxy/gl.h>
// After epoxy: GLFW must not pull in a GL header of its own.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "core/timer.h"
#include "io/npy.h"
#include "render/image.h"
#include "render/renderer.h"
#include "run/run_writer.h"
#include "viewer/frame_pacer.h"
#include "viewer/gl_window.h"
#include "viewer/interaction.h"
#include "viewer/panel.h"

namespace clothsim::viewer {
namespace {

constexpr double kPickRadius = 12.0;      // pixels around the cursor that pick a particle
constexpr double kOrbitPerPixel = 0.008;  // rad of orbit per pixel of mouse motion
constexpr double kOrbitPerKey = 0.06;     // rad per key press (or repeat)
constexpr double kPanPerKey = 0.05;       // fraction of the view height per key press
constexpr double kZoomPerNotch = 0.9;     // distance factor per scroll notch or key press

class Viewer {
 public:
  Viewer(Session& session, const ViewerOptions& options);
  ~Viewer();
  Viewer(const Viewer&) = delete;
  Viewer& operator=(const Viewer&) = delete;

  int run();

 private:
  enum class MouseMode { none, orbit, pan, drag, drag_sphere, cut };

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
  // Grabs the sphere under the cursor at pixel (x, y) if there is one and the particle `picked`
  // (-1: none) is not nearer the eye; with `behind_sheet` (alt held) even if it is.
  bool grab_sphere(double x, double y, long picked, bool behind_sheet);
  // The grabbed sphere follows the cursor over the next `duration` s of simulated time.
  void drag_sphere(double duration);
  void toggle_self_collision();
  // Adds a sphere of the panel's radius beside the sheet (the panel's Add sphere button).
  void add_sphere();
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
  std::size_t grabbed_sphere_ = 0;  // collider index, while mouse_mode_ is drag_sphere
  Vec3 sphere_plane_point_;         // m: the sphere's centre at the grab (its drag plane's point)
  Vec3 sphere_grab_offset_;         // m: from the point grabbed on that plane to the centre
  long hovered_ = -1;
  std::size_t cut_count_ = 0;  // connectors broken by the current cut
  bool quit_ = false;
  std::uint64_t screenshot_count_ = 0;
};

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
  if (button == GLFW_MOUSE_BUTTON_LEFT && grab_sphere(x, y, picked, (mods & GLFW_MOD_ALT) != 0)) return;
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
    case MouseMode::orbit: camera_.orbit(-dx * kOrbitPerPixel, dy * kOrbitPerPixel); break;
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
    case MouseMode::drag:         // the target follows the cursor in drag_grabbed(), once per frame
    case MouseMode::drag_sphere:  // and in drag_sphere()
    case MouseMode::none: break;
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
    case GLFW_KEY_F: frame_camera(); break;
    case GLFW_KEY_C:
      if (!repeat) toggle_self_collision();
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
    case GLFW_KEY_Q: quit_ = true; break;
    default: break;
  }
}

void Viewer::drag_grabbed(double duration) {
  if (grabbed_ < 0) return;
  const auto [x, y] = cursor_pixels();
  const std::optional<Vec3> target = drag_target(camera_, grab_plane_point_, x, y, width_, height_);
  if (!target) return;
  session_.drag(static_cast<std::uint32_t>(grabbed_), *target, duration);
}

bool Viewer::grab_sphere(double x, double y, long picked, bool behind_sheet) {
  const Simulation& simulation = session_.simulation();
  const std::optional<SphereHit> hit = pick_sphere(camera_, simulation.model(), session_.time(), x, y, width_, height_);
  if (!hit) return false;
  if (picked >= 0 && !behind_sheet) {
    const Vec3& particle = simulation.state().position[static_cast<std::size_t>(picked)];
    if (norm(particle - camera_.eye()) < hit->distance) return false;  // the sheet is in front
  }
  grabbed_sphere_ = hit->collider;
  sphere_plane_point_ = session_.sphere_center(hit->collider);
  const std::optional<Vec3> grabbed_point = drag_target(camera_, sphere_plane_point_, x, y, width_, height_);
  sphere_grab_offset_ = grabbed_point ? sphere_plane_point_ - *grabbed_point : Vec3{};
  mouse_mode_ = MouseMode::drag_sphere;
  panel_.status = "dragging collider " + std::to_string(hit->collider) + " (a sphere)";
  return true;
}

void Viewer::drag_sphere(double duration) {
  const auto [x, y] = cursor_pixels();
  const std::optional<Vec3> target = drag_target(camera_, sphere_plane_point_, x, y, width_, height_);
  if (target) session_.move_sphere(grabbed_sphere_, *target + sphere_grab_offset_, duration);
}

void Viewer::toggle_self_collision() {
  try {
    session_.set_self_collision(!session_.self_collision());
    panel_.status = session_.self_collision() ? "self-collision on" : "self-collision off";
  } catch (const InputError& error) {
    panel_.status = error.what();
  }
}

void Viewer::add_sphere() {
  const double radius = panel_.sphere_radius;
  const Vec3 centre = place_beside_sheet(camera_, session_.simulation().state().position, radius);
  const std::size_t collider = session_.add_sphere(centre, radius);
  char text[96];
  std::snprintf(text, sizeof text, "added collider %zu: a sphere of radius %.3g m", collider, radius);
  panel_.status = text;
}

void Viewer::release_grabbed() {
  if (grabbed_ >= 0) session_.release(static_cast<std::uint32_t>(grabbed_));
  grabbed_ = -1;
}

std::string Viewer::next_screenshot_path() {
  std::string name;
  for (char c : session_.scene().name) {
    const bool safe =
        (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
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

  FrameBenchmark benchmark;
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
    if (frame == 1) benchmark.start();

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
      if (mouse_mode_ == MouseMode::drag_sphere) drag_sphere(moving ? duration : 0.0);
      double advanced = 0.0;
      const Stopwatch simulation_watch;
      if (moving) {
        advanced = scripted || step ? session_.advance(duration)
                                    : session_.advance(duration, FramePacer::kWorkBudget, FramePacer::kPiece);
      }
      if (step) session_.set_playing(false);
      pacer_.record(wall_interval, advanced, session_.playing());
      // Frame 1's interval holds the start-up: the benchmark starts after it.
      if (frame >= 2) benchmark.record(wall_interval, advanced, simulation_watch.seconds());
    }
    if (session_.failed()) {
      session_.set_playing(false);
      if (!reported_failure) {
        std::fprintf(stderr, "clothsim: error: simulation failed %s\n",
                     session_.simulation().failure()->message.c_str());
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
    if (panel_.add_sphere_requested) {
      panel_.add_sphere_requested = false;
      add_sphere();
    }
    draw_ui();
    glfwSwapBuffers(window_);

    if (options_.frames > 0 && frame >= options_.frames) break;
    if (options_.benchmark_frames > 0 && frame >= options_.benchmark_frames + 1) break;
  }

  if (options_.benchmark_frames > 0) {
    const std::string window = std::to_string(width_) + "x" + std::to_string(height_);
    benchmark.print(session_.scene().name, session_.simulation(), window);
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
