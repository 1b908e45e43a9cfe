// `clothsim view` end to end: the real executable in a real window on a virtual X server (Xvfb,
// started by each test on a display it picks itself with -displayfd, so parallel tests never
// collide), rendering with Mesa where there is no GPU.
//
// What they pin down (docs/viewer.md):
//   - a scripted drag runs for its frames and exits 0; the dragged particle ends at its target,
//     the anchor stays put; the screenshots are PNGs of the window size that show the sheet;
//   - a scripted run is reproducible bit for bit, and a paused one does not move;
//   - bad input exits 2 naming the file, event and field, before any window opens;
//   - no display exits 3 with advice; --benchmark-frames prints its figures.
// Xvfb comes from scripts/install-deps.sh; without it the tests fail and say so (never skip).
#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "io/npy.h"
#include "render/image.h"

#include "cli_harness.h"
#include "test_checks.h"

namespace clothsim {
namespace {

namespace fs = std::filesystem;

// The paper's material on a 7 x 7 lattice, the centre particle (index 24) anchored at the origin.
constexpr const char* kPaperArgs = "7,7,1,4,1,1400,200,80,5,1";
constexpr std::size_t kParticles = 49;
constexpr std::size_t kCentre = 24;

using Result = checks::ProcessResult;
using checks::read_text;
using checks::write_text;

// A virtual X server for the life of the object.
class VirtualDisplay {
 public:
  VirtualDisplay() {
    int fds[2];
    if (::pipe(fds) != 0) return;
    pid_ = ::fork();
    if (pid_ == 0) {
      ::close(fds[0]);
      const int null = ::open("/dev/null", O_WRONLY);
      ::dup2(null, STDOUT_FILENO);
      ::dup2(null, STDERR_FILENO);
      const std::string fd = std::to_string(fds[1]);
      ::execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1024x768x24", "-nolisten", "tcp",
               static_cast<char*>(nullptr));
      ::_exit(127);
    }
    ::close(fds[1]);
    // Xvfb writes the display number and a newline once it accepts connections.
    std::string number;
    pollfd poll_fd{fds[0], POLLIN, 0};
    while (number.find('\n') == std::string::npos && ::poll(&poll_fd, 1, 20000) > 0) {
      char buffer[16];
      const ssize_t count = ::read(fds[0], buffer, sizeof buffer);
      if (count <= 0) break;
      number.append(buffer, static_cast<std::size_t>(count));
    }
    ::close(fds[0]);
    if (number.find('\n') != std::string::npos) name_ = ":" + number.substr(0, number.find('\n'));
  }
  ~VirtualDisplay() {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  VirtualDisplay(const VirtualDisplay&) = delete;
  VirtualDisplay& operator=(const VirtualDisplay&) = delete;

  // ":1", or "" if Xvfb did not start.
  const std::string& name() const { return name_; }

 private:
  pid_t pid_ = -1;
  std::string name_;
};

class ViewCommand : public cli_harness::ToolTest {
 protected:
  ViewCommand() : ToolTest("view") {}

  // Runs clothsim with `args` in work_, with DISPLAY set to `display` (unset when empty) and no
  // Wayland display; a run that outlasts 120 s is killed and fails the test.
  Result run(const std::vector<std::string>& args, const std::string& display) const {
    std::optional<std::string> value;
    if (!display.empty()) value = display;
    cli_harness::ChildSetup setup;
    setup.environment = {{"DISPLAY", value}, {"WAYLAND_DISPLAY", std::nullopt}};
    const pid_t pid = start(args, setup);
    return cli_harness::wait_clothsim(pid, root_, std::chrono::seconds(120));
  }
};

// Fraction of pixels that differ clearly from the top-left one (the background), and the number
// of distinct colours: a blank or uniform image has (0, 1).
std::pair<double, std::size_t> image_content(const render::Image& image) {
  const std::uint8_t* background = image.pixel(0, 0);
  std::size_t different = 0;
  std::set<std::uint32_t> colours;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      const int distance =
          std::abs(p[0] - background[0]) + std::abs(p[1] - background[1]) + std::abs(p[2] - background[2]);
      if (distance > 30) ++different;
      colours.insert(static_cast<std::uint32_t>(p[0]) << 16 | static_cast<std::uint32_t>(p[1]) << 8 | p[2]);
    }
  }
  return {static_cast<double>(different) / (image.width * image.height), colours.size()};
}

Vec3 particle_position(const NpyArray& state, std::size_t particle) {
  return {state.data[3 * particle], state.data[3 * particle + 1], state.data[3 * particle + 2]};
}

constexpr const char* kDragScript = R"({
  "description": "lift a corner of the sheet",
  "events": [
    {"at": 0.1, "drag": {"row": 0, "col": 0, "to": [-2.0, 2.0, -2.5], "duration": 0.5}},
    {"frame": 30, "screenshot": "middle.png"}
  ]
})";

std::vector<std::string> drag_arguments() {
  return {"view",         "--paper-args", kPaperArgs,  "--script", "drag.json", "--frames", "45", "--screenshot-at",
          "45:final.png", "--dump-state", "state.npy", "--size",   "320x240"};
}

TEST_F(ViewCommand, ScriptedDragEndsAtItsTargetWithScreenshotsOfTheSheet) {
  const VirtualDisplay display;
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start; install it with scripts/install-deps.sh";
  write_text(work_ / "drag.json", kDragScript);
  const Result result = run(drag_arguments(), display.name());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("screenshot: middle.png (320x240, t = 0.5 s)"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("screenshot: final.png (320x240, t = 0.75 s)"), std::string::npos) << result.out;

  // The drag started at 0.1 s and took 0.5 s: at 0.75 s the corner is at its target.
  const NpyArray state = read_npy((work_ / "state.npy").string());
  ASSERT_EQ(state.shape, (std::vector<std::size_t>{kParticles, 3}));
  EXPECT_LT(norm(particle_position(state, 0) - Vec3{-2.0, 2.0, -2.5}), 1e-9);
  EXPECT_EQ(particle_position(state, kCentre), Vec3{});         // the scene's anchor stayed put
  EXPECT_LT(particle_position(state, kParticles - 1).y, -0.1);  // the far corner hangs down

  const render::Image final_image = render::read_png((work_ / "final.png").string());
  const render::Image middle_image = render::read_png((work_ / "middle.png").string());
  EXPECT_EQ(final_image.width, 320);
  EXPECT_EQ(final_image.height, 240);
  const auto [covered, colours] = image_content(final_image);
  EXPECT_GT(covered, 0.03) << "the sheet covers too little of the picture";
  EXPECT_GT(colours, 50u) << "a shaded sheet has many colours";
  EXPECT_NE(final_image.rgb, middle_image.rgb);  // the sheet moved between frames 30 and 45
}

// Fraction of pixels in the sheet's front colour (orange: red well above green and blue; the
// yellow anchor marker and the grey grid do not count).
double sheet_share(const render::Image& image) {
  std::size_t sheet = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      if (p[0] > p[1] + 40 && p[0] > p[2] + 60) ++sheet;
    }
  }
  return static_cast<double>(sheet) / (image.width * image.height);
}

// A free sheet falls 19.6 m in 2 s, more than three times its own width: the view follows it (it
// frames everything the sheet has covered) instead of keeping the first frame's shot, where the
// sheet would have left the picture after half a second.
TEST_F(ViewCommand, TheViewKeepsAFallingSheetInThePicture) {
  const VirtualDisplay display;
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start; install it with scripts/install-deps.sh";
  const Result result =
      run({"view", "--paper-args", kPaperArgs, "--anchor", "none", "--frames", "120", "--screenshot-at", "1:start.png",
           "--screenshot-at", "120:fallen.png", "--dump-state", "state.npy", "--size", "320x240"},
          display.name());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const NpyArray state = read_npy((work_ / "state.npy").string());
  EXPECT_LT(particle_position(state, kCentre).y, -15.0) << "the sheet did fall";
  const double start = sheet_share(render::read_png((work_ / "start.png").string()));
  const double fallen = sheet_share(render::read_png((work_ / "fallen.png").string()));
  EXPECT_GT(start, 0.05);
  EXPECT_GT(fallen, 0.002) << "the fallen sheet is out of the picture";
}

// A scripted cut across the sheet under its anchored centre: the rows below the cut fall away,
// and the torn sheet is drawn (the split mesh) without trouble.
TEST_F(ViewCommand, ScriptedCutTearsTheSheetAndTheLowerPartFalls) {
  const VirtualDisplay display;
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start; install it with scripts/install-deps.sh";
  write_text(work_ / "cut.json", R"({"events": [{"at": 0.1, "cut": {"from": [4.5, -1], "to": [4.5, 7]}},
                                                 {"frame": 60, "screenshot": "torn.png"}]})");
  const Result result = run({"view", "--paper-args", kPaperArgs, "--script", "cut.json", "--frames", "60",
                             "--dump-state", "state.npy", "--size", "320x240"},
                            display.name());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const NpyArray state = read_npy((work_ / "state.npy").string());
  ASSERT_EQ(state.shape, (std::vector<std::size_t>{kParticles, 3}));
  // Row 4 hangs from the anchored centre; row 5, cut loose 0.9 s ago, fell about 4 m further.
  EXPECT_LT(particle_position(state, 5 * 7 + 3).y, particle_position(state, 4 * 7 + 3).y - 2.0);
  const auto [covered, colours] = image_content(render::read_png((work_ / "torn.png").string()));
  EXPECT_GT(covered, 0.01);
  EXPECT_GT(colours, 50u);
}

TEST_F(ViewCommand, ScriptedRunsAreReproducibleBitForBit) {
  const VirtualDisplay display;
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start; install it with scripts/install-deps.sh";
  write_text(work_ / "drag.json", kDragScript);
  ASSERT_EQ(run(drag_arguments(), display.name()).exit_code, 0);
  fs::rename(work_ / "state.npy", root_ / "first.npy");
  ASSERT_EQ(run(drag_arguments(), display.name()).exit_code, 0);
  EXPECT_EQ(read_text(root_ / "first.npy"), read_text(work_ / "state.npy"));
}

TEST_F(ViewCommand, PausedRunStandsStillAndQuitEndsIt) {
  const VirtualDisplay display;
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start; install it with scripts/install-deps.sh";
  write_text(work_ / "pause.json", R"({"events": [{"at": 0, "pause": true}, {"frame": 5, "quit": true}]})");
  const Result result = run({"view", "--paper-args", kPaperArgs, "--script", "pause.json", "--frames", "100000",
                             "--dump-state", "state.npy", "--size", "200x150", "--hide-panel"},
                            display.name());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const NpyArray state = read_npy((work_ / "state.npy").string());
  ASSERT_EQ(state.shape, (std::vector<std::size_t>{kParticles, 3}));
  // Paused from frame 0: the flat rest lattice, spacing 1, centred on the origin.
  for (std::size_t p = 0; p < kParticles; ++p) {
    EXPECT_EQ(particle_position(state, p),
              (Vec3{static_cast<double>(p % 7) - 3.0, 0.0, static_cast<double>(p / 7) - 3.0}));
  }
}

// Where two pictures differ clearly: the centroid of those pixels (x, y) and their count.
std::pair<std::array<double, 2>, std::size_t> difference(const render::Image& a, const render::Image& b) {
  std::array<double, 2> sum{};
  std::size_t count = 0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      const std::uint8_t* p = a.pixel(x, y);
      const std::uint8_t* q = b.pixel(x, y);
      if (std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]) <= 30) continue;
      sum[0] += x;
      sum[1] += y;
      ++count;
    }
  }
  if (count > 0) sum = {sum[0] / static_cast<double>(count), sum[1] / static_cast<double>(count)};
  return {sum, count};
}

// A sphere added and moved by a script is drawn where it is: paused (so the sheet and the camera
// stand still), the sphere appears once added, and appears elsewhere once moved. The obstacle
// events and the self-collision switch run in the real window.
TEST_F(ViewCommand, AnAddedSphereIsDrawnWhereItIsMoved) {
  const VirtualDisplay display;
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start; install it with scripts/install-deps.sh";
  write_text(work_ / "sphere.json", R"({"events": [
      {"frame": 0, "pause": true},
      {"frame": 1, "screenshot": "none.png"},
      {"frame": 2, "add_sphere": {"center": [-2, 1.5, 0], "radius": 0.8}},
      {"frame": 2, "self_collision": true},
      {"frame": 3, "screenshot": "added.png"},
      {"frame": 4, "move_sphere": {"sphere": 0, "to": [2, 1.5, 0], "duration": 0.5}},
      {"frame": 4, "self_collision": false},
      {"frame": 5, "screenshot": "moved.png"}]})");
  const Result result = run({"view", "--paper-args", kPaperArgs, "--script", "sphere.json", "--frames", "5", "--size",
                             "320x240", "--hide-panel"},
                            display.name());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const render::Image none = render::read_png((work_ / "none.png").string());
  const auto [added_at, added_pixels] = difference(none, render::read_png((work_ / "added.png").string()));
  const auto [moved_at, moved_pixels] = difference(none, render::read_png((work_ / "moved.png").string()));
  EXPECT_GT(added_pixels, 200u) << "the added sphere is not drawn";
  EXPECT_GT(moved_pixels, 200u) << "the moved sphere is not drawn";
  EXPECT_GT(std::hypot(moved_at[0] - added_at[0], moved_at[1] - added_at[1]), 20.0)
      << "the sphere is drawn in the same place after it moved";
}

TEST_F(ViewCommand, BadInputExitsTwoBeforeAnyWindowOpens) {
  write_text(work_ / "bad.json", R"({"events": [{"at": 0, "pause": true},
    {"at": 1, "drag": {"row": 0, "col": 0, "to": [0, 1, 0], "duration": -2}}]})");
  // No DISPLAY: had a window been tried, the exit code would be 3.
  Result result = run({"view", "--paper-args", kPaperArgs, "--script", "bad.json", "--dump-state", "state.npy"}, "");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find(
                "clothsim: error: bad.json: field 'events[1].drag.duration': must be a number in (0, 86400], got -2"),
            std::string::npos)
      << result.err;
  EXPECT_FALSE(fs::exists(work_ / "state.npy"));

  write_text(work_ / "rows.json", R"({"events": [{"at": 0, "pin": {"row": 7, "col": 0}}]})");
  result = run({"view", "--paper-args", kPaperArgs, "--script", "rows.json"}, "");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("rows.json: field 'events[0].pin.row': must be in [0, 6]"), std::string::npos)
      << result.err;

  result = run({"view", "paper-fig4", "--screenshot-at", "ten:shot.png"}, "");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("--screenshot-at: expects FRAME:PATH"), std::string::npos) << result.err;

  result = run({"view", "paper-fig4", "--size", "10x10"}, "");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("--size: expects WIDTHxHEIGHT"), std::string::npos) << result.err;

  result = run({"view", "paper-fig4", "--gravity", "0,-5"}, "");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("--gravity"), std::string::npos) << result.err;

  result = run({"view"}, "");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("view: needs a SCENE"), std::string::npos) << result.err;
}

TEST_F(ViewCommand, NoDisplayIsAnOutputErrorWithAdvice) {
  const Result result = run({"view", "--paper-args", kPaperArgs, "--frames", "3"}, "");
  EXPECT_EQ(result.exit_code, 3);
  EXPECT_NE(result.err.find("clothsim: error: cannot open a window"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("xvfb-run -a clothsim view"), std::string::npos) << result.err;
}

TEST_F(ViewCommand, BenchmarkPrintsFramesPerSecondAndRealTimeRatio) {
  const VirtualDisplay display;
  ASSERT_FALSE(display.name().empty()) << "Xvfb did not start; install it with scripts/install-deps.sh";
  const Result result =
      run({"view", "--paper-args", kPaperArgs, "--benchmark-frames", "20", "--size", "200x150"}, display.name());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("benchmark: 20 frames in "), std::string::npos) << result.out;
  EXPECT_NE(result.out.find(" fps (median frame "), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("x real time"), std::string::npos) << result.out;
}

}  // namespace
}  // namespace clothsim
