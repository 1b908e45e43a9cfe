// End-to-end tests of the pictures of `clothsim run` (final.png, animation.mp4): each runs the
// real executable (CLOTHSIM_EXE) in a fresh folder and reads the output back with ffprobe and
// libpng. What they pin down (docs/cli.md, docs/rendering.md):
//   - the video has one frame per output frame, at the output fps, the requested size, H.264
//     in yuv420p; final.png is the last frame, at the requested size, showing the sheet;
//   - --render none|image|video write exactly the files they name; none creates no OpenGL
//     context at all (it succeeds where EGL is broken);
//   - bad --size/--render/--camera/--mesh/--show exit 2 naming the flag and write nothing;
//   - without ffmpeg or without a working EGL the run fails before simulating: exit 3, a message
//     suggesting --render none, and nothing written.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/image.h"
#include "test_checks.h"

extern char** environ;

namespace clothsim::render {
namespace {

namespace fs = std::filesystem;

constexpr const char* kSmallPaperArgs = "5,5,1,4,1,1400,200,80,5,1";

using Result = checks::ProcessResult;
using checks::read_text;

std::set<std::string> entries(const fs::path& folder) {
  std::set<std::string> names;
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(folder)) {
    names.insert(fs::relative(entry.path(), folder).string());
  }
  return names;
}

class RunPictures : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::path(CLOTHSIM_TEST_TMPDIR) / "run_pictures" / info->name();
    fs::remove_all(root_);
    work_ = root_ / "work";
    fs::create_directories(work_);
  }

  // Runs clothsim in work_ with `args`; `environment` entries (NAME=VALUE) replace or add to
  // this process's environment.
  Result run(const std::vector<std::string>& args, const std::vector<std::string>& environment = {}) const {
    std::vector<std::string> words = {CLOTHSIM_EXE};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& word : words) argv.push_back(word.data());
    argv.push_back(nullptr);
    std::vector<std::string> variables;
    for (char** variable = environ; *variable != nullptr; ++variable) {
      const std::string text = *variable;
      bool replaced = false;
      for (const std::string& extra : environment) {
        if (text.substr(0, text.find('=') + 1) == extra.substr(0, extra.find('=') + 1)) replaced = true;
      }
      if (!replaced) variables.push_back(text);
    }
    variables.insert(variables.end(), environment.begin(), environment.end());
    std::vector<char*> envp;
    for (std::string& variable : variables) envp.push_back(variable.data());
    envp.push_back(nullptr);

    const std::string out_path = (root_ / "stdout.txt").string();
    const std::string err_path = (root_ / "stderr.txt").string();
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    // posix_spawn_file_actions_addchdir_np needs glibc 2.29; Debian 12 has 2.36.
    posix_spawn_file_actions_addchdir_np(&actions, work_.c_str());
    pid_t pid = -1;
    Result result;
    if (posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), envp.data()) == 0) {
      int status = 0;
      if (::waitpid(pid, &status, 0) == pid) {
        if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
        if (WIFSIGNALED(status)) result.exit_code = 128 + WTERMSIG(status);
      }
    }
    posix_spawn_file_actions_destroy(&actions);
    result.out = read_text(out_path);
    result.err = read_text(err_path);
    return result;
  }

  Result small_run(const std::vector<std::string>& extra, const std::vector<std::string>& environment = {}) const {
    std::vector<std::string> args = {"run",   "--paper-args", kSmallPaperArgs, "--duration", "0.5",
                                     "--fps", "20",           "--out",         "run",        "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run(args, environment);
  }

  fs::path root_;
  fs::path work_;
};

std::string describe(const Result& result) {
  return "exit code " + std::to_string(result.exit_code) + "\n--- stdout\n" + result.out + "--- stderr\n" + result.err;
}

// ffprobe's view of the first video stream, frames counted by decoding.
nlohmann::json probe(const fs::path& video) {
  const std::string command =
      "ffprobe -v error -select_streams v:0 -count_frames -show_entries "
      "stream=codec_name,pix_fmt,width,height,nb_read_frames,r_frame_rate -of json '" +
      video.string() + "' 2>&1";
  std::FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return {};
  std::string text;
  char buffer[4096];
  std::size_t got = 0;
  while ((got = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) text.append(buffer, got);
  const int status = ::pclose(pipe);
  EXPECT_EQ(status, 0) << "ffprobe failed (is ffmpeg installed? scripts/install-deps.sh installs it): " << text;
  const nlohmann::json json = nlohmann::json::parse(text, nullptr, false);
  if (json.is_discarded() || !json.contains("streams") || json["streams"].empty()) {
    ADD_FAILURE() << "ffprobe output: " << text;
    return {};
  }
  return json["streams"][0];
}

// Frame `frame` of `video`, decoded by ffmpeg into a PNG at `png`.
Image decoded_frame(const fs::path& video, int frame, const fs::path& png) {
  const std::string command = "ffmpeg -v error -y -i '" + video.string() + "' -vf 'select=eq(n\\," +
                              std::to_string(frame) + ")' -frames:v 1 '" + png.string() + "' 2>&1";
  const int status = std::system(command.c_str());
  EXPECT_EQ(status, 0) << command;
  return read_png(png.string());
}

// Mean absolute difference per colour channel of two pictures of the same size, in 0..255.
double mean_difference(const Image& a, const Image& b) {
  EXPECT_EQ(a.rgb.size(), b.rgb.size());
  double sum = 0.0;
  for (std::size_t i = 0; i < a.rgb.size() && i < b.rgb.size(); ++i) sum += std::abs(int(a.rgb[i]) - int(b.rgb[i]));
  return a.rgb.empty() ? 0.0 : sum / static_cast<double>(a.rgb.size());
}

TEST_F(RunPictures, VideoHasOneFramePerOutputFrameAndFinalPngTheRequestedSize) {
  const Result result = small_run({"--size", "320x240"});
  ASSERT_EQ(result.exit_code, 0) << describe(result);
  const nlohmann::json stream = probe(work_ / "run" / "animation.mp4");
  EXPECT_EQ(stream.value("codec_name", ""), "h264");
  EXPECT_EQ(stream.value("pix_fmt", ""), "yuv420p");
  EXPECT_EQ(stream.value("width", 0), 320);
  EXPECT_EQ(stream.value("height", 0), 240);
  EXPECT_EQ(stream.value("r_frame_rate", ""), "20/1");
  // Frames 0 .. 10: t = 0, 0.05, ..., 0.5 s.
  EXPECT_EQ(stream.value("nb_read_frames", ""), "11");

  // summary.json lists both, with what ffprobe saw.
  const nlohmann::json summary = nlohmann::json::parse(read_text(work_ / "run" / "summary.json"));
  const nlohmann::json& files = summary["files"];
  EXPECT_EQ(files["animation.mp4"]["frames"], 11);
  EXPECT_EQ(files["animation.mp4"]["fps"], 20);
  EXPECT_EQ(files["animation.mp4"]["codec"], "h264");
  EXPECT_EQ(files["final.png"]["frame"], 10);
  EXPECT_EQ(files["final.png"]["width"], 320);

  const Image image = read_png((work_ / "run" / "final.png").string());
  EXPECT_EQ(image.width, 320);
  EXPECT_EQ(image.height, 240);
  // The sheet is there: many strongly red pixels (the default front colour is terracotta).
  int red = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      if (p[0] > p[1] + 60 && p[0] > p[2] + 60) ++red;
    }
  }
  EXPECT_GT(red, 320 * 240 / 20);

  // final.png is the video's last frame (up to the video's lossy coding), not its first.
  const Image last = decoded_frame(work_ / "run" / "animation.mp4", 10, work_ / "last.png");
  const Image first = decoded_frame(work_ / "run" / "animation.mp4", 0, work_ / "first.png");
  const double to_last = mean_difference(image, last);
  EXPECT_LT(to_last, 6.0);
  EXPECT_LT(2.0 * to_last, mean_difference(image, first)) << "the sheet moved between the first and last frames";
}

TEST_F(RunPictures, OddSizesArePaddedInTheVideoOnly) {
  const Result result = small_run({"--size", "321x241", "--duration", "0.1"});
  ASSERT_EQ(result.exit_code, 0) << describe(result);
  const nlohmann::json stream = probe(work_ / "run" / "animation.mp4");
  EXPECT_EQ(stream.value("width", 0), 322);
  EXPECT_EQ(stream.value("height", 0), 242);
  EXPECT_EQ(stream.value("nb_read_frames", ""), "3");
  const Image image = read_png((work_ / "run" / "final.png").string());
  EXPECT_EQ(image.width, 321);
  EXPECT_EQ(image.height, 241);
}

TEST_F(RunPictures, RenderFlagWritesExactlyTheNamedFiles) {
  const std::set<std::string> data = checks::run_data_paths("run");
  struct Case {
    const char* render;
    std::vector<std::string> pictures;
  };
  for (const Case& c : {Case{"none", {}}, Case{"image", {"run/final.png"}}, Case{"video", {"run/animation.mp4"}}}) {
    fs::remove_all(work_);
    fs::create_directories(work_);
    const Result result = small_run({"--render", c.render, "--size", "64x48", "--duration", "0.1"});
    ASSERT_EQ(result.exit_code, 0) << describe(result);
    std::set<std::string> expected = data;
    expected.insert(c.pictures.begin(), c.pictures.end());
    EXPECT_EQ(entries(work_), expected) << "--render " << c.render;
  }
}

// Each set of camera, mesh and overlay flags changes the picture: compared with the same run
// without them, at the requested size.
TEST_F(RunPictures, CameraMeshAndOverlayFlagsChangeThePicture) {
  const auto picture = [this](const std::vector<std::string>& flags) {
    fs::remove_all(work_);
    fs::create_directories(work_);
    std::vector<std::string> args = {"--render", "image", "--size", "96x64", "--duration", "0.1"};
    args.insert(args.end(), flags.begin(), flags.end());
    const Result result = small_run(args);
    EXPECT_EQ(result.exit_code, 0) << describe(result);
    return read_png((work_ / "run" / "final.png").string());
  };
  const Image plain = picture({});
  for (const std::vector<std::string>& flags :
       {std::vector<std::string>{"--camera", "follow", "--mesh", "cell-centres"},
        std::vector<std::string>{"--camera", "-30,60", "--show", "connectors,radials,wireframe"},
        std::vector<std::string>{"--camera", "10,20,15", "--show", "no-ground,no-anchors", "--samples", "1"},
        std::vector<std::string>{"--show", "connectors,radials,wireframe"},
        std::vector<std::string>{"--show", "no-ground"}}) {
    const Image image = picture(flags);
    EXPECT_EQ(image.width, 96);
    EXPECT_EQ(image.height, 64);
    std::size_t differing = 0;
    for (std::size_t i = 0; i < image.rgb.size() && i < plain.rgb.size(); ++i) {
      if (image.rgb[i] != plain.rgb[i]) ++differing;
    }
    EXPECT_GT(differing, 100u) << flags[0] << " " << flags[1] << ": the flags changed nothing";
  }
}

TEST_F(RunPictures, BadFlagsExitTwoNamingTheFlagAndWriteNothing) {
  const std::vector<std::vector<std::string>> cases = {
      {"--size", "0x100"},      {"--size", "1280"},      {"--size", "100x99999"}, {"--size", "axb"},
      {"--size", "1280x720x3"}, {"--size", "-5x10"},     {"--render", "movie"},   {"--camera", "90"},
      {"--camera", "0,95"},     {"--camera", "0,10,-1"}, {"--camera", "zoom"},    {"--mesh", "quads"},
      {"--show", "springs"},    {"--samples", "0"},      {"--samples", "17"},     {"--samples", "2.5"},
  };
  for (const std::vector<std::string>& flags : cases) {
    const Result result = small_run(flags);
    EXPECT_EQ(result.exit_code, 2) << flags[0] << " " << flags[1] << "\n" << describe(result);
    EXPECT_NE(result.err.find(flags[0]), std::string::npos) << describe(result);
    EXPECT_TRUE(entries(work_).empty()) << flags[0] << " " << flags[1];
  }
  const Result size = small_run({"--size", "0x100"});
  EXPECT_NE(size.err.find("[16, 8192]"), std::string::npos) << size.err;
}

// Ctrl-C in a terminal sends SIGINT to the whole foreground process group. The run must end as
// an interrupted run (exit 130) with a complete video of the frames kept: ffmpeg must not get
// the signal too.
TEST_F(RunPictures, CtrlCKeepsACompleteVideoOfTheFramesKept) {
  std::vector<std::string> words = {CLOTHSIM_EXE, "run",   "--paper-args", kSmallPaperArgs, "--duration",
                                    "100000",     "--fps", "20",           "--size",        "64x48",
                                    "--out",      "run",   "--quiet"};
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  const std::string err_path = (root_ / "stderr.txt").string();
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addchdir_np(&actions, work_.c_str());
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);  // a group, like a shell job
  posix_spawnattr_setpgroup(&attributes, 0);
  pid_t pid = -1;
  ASSERT_EQ(posix_spawn(&pid, argv[0], &actions, &attributes, argv.data(), environ), 0);
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  // Wait until a few frames are in the partial folder's positions.npy, then Ctrl-C the group.
  const fs::path positions = work_ / ("run.partial-" + std::to_string(pid)) / "positions.npy";
  for (int wait = 0; wait < 600; ++wait) {
    std::error_code error;
    if (fs::file_size(positions, error) > 128 + 5 * 25 * 24 && !error) break;
    ::usleep(10000);
  }
  ASSERT_EQ(::kill(-pid, SIGINT), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << read_text(err_path);
  EXPECT_EQ(WEXITSTATUS(status), 130) << read_text(err_path);
  const nlohmann::json summary = nlohmann::json::parse(read_text(work_ / "run" / "summary.json"));
  EXPECT_EQ(summary["status"], "interrupted");
  const int frames = summary["frames"].get<int>();
  EXPECT_GE(frames, 5);
  const nlohmann::json stream = probe(work_ / "run" / "animation.mp4");
  EXPECT_EQ(stream.value("nb_read_frames", ""), std::to_string(frames));
}

// A simulation that blows up keeps its good frames (exit 1), and its pictures show them.
TEST_F(RunPictures, FailedSimulationKeepsPicturesOfTheFramesKept) {
  const Result result = small_run(
      {"--integrator", "symplectic-euler", "--time-step", "0.5", "--duration", "5", "--fps", "2", "--size", "64x48"});
  ASSERT_EQ(result.exit_code, 1) << describe(result);
  const nlohmann::json summary = nlohmann::json::parse(read_text(work_ / "run" / "summary.json"));
  EXPECT_EQ(summary["status"], "failed");
  const nlohmann::json stream = probe(work_ / "run" / "animation.mp4");
  EXPECT_EQ(stream.value("nb_read_frames", ""), std::to_string(summary["frames"].get<int>()));
  EXPECT_TRUE(fs::exists(work_ / "run" / "final.png"));
}

// ffmpeg failing in the middle of the run (here a stand-in that reads a little, complains and
// exits 1) is an output error: exit 3 with ffmpeg's message, and no folder left behind.
TEST_F(RunPictures, FfmpegFailingMidRunExitsThreeWithItsMessageAndLeavesNothing) {
  const fs::path bin = root_ / "bin";
  fs::create_directories(bin);
  const fs::path fake = bin / "ffmpeg";
  {
    std::ofstream script(fake);
    script << "#!/bin/sh\n"
              "case \"$*\" in *-version*) exit 0;; esac\n"
              "head -c 20000 > /dev/null\n"
              "echo 'stand-in ffmpeg: the encoder gave up' >&2\n"
              "exit 1\n";
  }
  fs::permissions(fake, fs::perms::owner_all);
  const char* path = std::getenv("PATH");
  const Result result = small_run({"--size", "64x48", "--duration", "2"},
                                  {"PATH=" + bin.string() + ":" + (path != nullptr ? path : "/usr/bin:/bin")});
  EXPECT_EQ(result.exit_code, 3) << describe(result);
  EXPECT_NE(result.err.find("the encoder gave up"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("animation.mp4"), std::string::npos) << result.err;
  EXPECT_TRUE(entries(work_).empty());
}

TEST_F(RunPictures, WithoutFfmpegTheRunFailsBeforeSimulatingAndWritesNothing) {
  // An empty PATH: clothsim itself is started by its full path, ffmpeg cannot be found.
  const fs::path empty = root_ / "empty-path";
  fs::create_directories(empty);
  const Result result = small_run({}, {"PATH=" + empty.string()});
  EXPECT_EQ(result.exit_code, 3) << describe(result);
  EXPECT_NE(result.err.find("ffmpeg"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("--render none"), std::string::npos) << result.err;
  EXPECT_TRUE(entries(work_).empty());
  // --render image needs no ffmpeg.
  const Result image = small_run({"--render", "image", "--size", "64x48"}, {"PATH=" + empty.string()});
  EXPECT_EQ(image.exit_code, 0) << describe(image);
}

TEST_F(RunPictures, WithoutEglTheRunFailsAndRenderNoneStillRuns) {
  // libglvnd finds EGL drivers through vendor files; pointing it at none leaves no EGL at all.
  const std::vector<std::string> no_egl = {"__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json",
                                           "__EGL_VENDOR_LIBRARY_DIRS=/nonexistent"};
  const Result result = small_run({"--render", "image"}, no_egl);
  EXPECT_EQ(result.exit_code, 3) << describe(result);
  EXPECT_NE(result.err.find("--render none"), std::string::npos) << result.err;
  EXPECT_TRUE(entries(work_).empty());
  // --render none never touches OpenGL, so it runs on the same broken machine.
  const Result none = small_run({"--render", "none"}, no_egl);
  EXPECT_EQ(none.exit_code, 0) << describe(none);
  EXPECT_TRUE(fs::exists(work_ / "run" / "positions.npy"));
  EXPECT_FALSE(fs::exists(work_ / "run" / "final.png"));
}

}  // namespace
}  // namespace clothsim::render
