// The ffmpeg child process behind VideoWriter (video_writer.h).
//
// posix_spawnp starts ffmpeg with its stdin on a pipe we write frames into and its stderr on an
// unlinked temporary file, read back only if ffmpeg fails. A file rather than a second pipe: a
// pipe nobody drains would block ffmpeg once it fills (64 KiB), and draining it needs a thread.
// The pipe's write end is close-on-exec so ffmpeg does not inherit it (else it would never see
// end of input). SIGPIPE is ignored while a writer lives, so a dead ffmpeg turns into an EPIPE
// error with its message rather than killing clothsim. ffmpeg runs in its own process group, so
// the terminal's Ctrl-C reaches only clothsim, which then finishes the video of the frames kept.
#include "render/video_writer.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

extern char** environ;

namespace clothsim::render {
namespace {

// Starts argv with stdin from `stdin_fd` and stdout and stderr to `output_fd` (/dev/null for -1),
// in a new process group. Returns the pid or throws with the reason.
pid_t spawn(const std::vector<std::string>& arguments, int stdin_fd, int output_fd) {
  std::vector<char*> argv;
  for (const std::string& argument : arguments) argv.push_back(const_cast<char*>(argument.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (stdin_fd >= 0) {
    posix_spawn_file_actions_adddup2(&actions, stdin_fd, STDIN_FILENO);
  } else {
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  }
  if (output_fd >= 0) {
    posix_spawn_file_actions_adddup2(&actions, output_fd, STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, output_fd, STDERR_FILENO);
  } else {
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  }
  // A process group of its own: Ctrl-C in the terminal goes to the terminal's foreground group,
  // and ffmpeg would stop (and fail the video) while clothsim finishes the interrupted run.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attributes, 0);
  pid_t pid = -1;
  const int error = posix_spawnp(&pid, argv[0], &actions, &attributes, argv.data(), environ);
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) {
    throw RenderError(
        "cannot run '" + arguments[0] + "': " + std::strerror(error) +
        (error == ENOENT ? " (is ffmpeg installed? install it, or use --render none or --render image)" : ""));
  }
  return pid;
}

int wait_for(pid_t pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return status;
}

std::string describe_status(int status) {
  if (status < 0) return "could not be waited for";
  if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return std::string("was killed by signal ") + strsignal(WTERMSIG(status));
  return "ended abnormally";
}

}  // namespace

struct VideoWriter::Impl {
  std::string path;
  std::string program;
  int width = 0;
  int height = 0;
  long frames = 0;
  pid_t pid = -1;
  int pipe_fd = -1;
  std::FILE* log = nullptr;  // ffmpeg's stdout and stderr
  void (*previous_sigpipe)(int) = SIG_DFL;

  std::string log_text() const {
    if (log == nullptr) return {};
    std::fflush(log);
    std::rewind(log);
    std::string text;
    char buffer[4096];
    std::size_t got = 0;
    while ((got = std::fread(buffer, 1, sizeof buffer, log)) > 0) text.append(buffer, got);
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    // Keep the end, where ffmpeg says what went wrong.
    constexpr std::size_t kMaxLog = 4000;
    if (text.size() > kMaxLog) text = "..." + text.substr(text.size() - kMaxLog);
    return text;
  }

  // Waits for ffmpeg and throws unless it exited 0.
  void wait_and_check(const std::string& context) {
    if (pipe_fd >= 0) {
      ::close(pipe_fd);
      pipe_fd = -1;
    }
    const int status = wait_for(pid);
    pid = -1;
    if (status >= 0 && WIFEXITED(status) && WEXITSTATUS(status) == 0 && context.empty()) return;
    std::string message = path + ": video encoding failed";
    if (!context.empty()) message += " (" + context + ")";
    message += ": " + program + " " + describe_status(status);
    const std::string text = log_text();
    if (!text.empty()) message += "; its output:\n" + text;
    throw RenderError(message);
  }
};

VideoWriter::VideoWriter(const std::string& path, int width, int height, int fps, std::string ffmpeg)
    : impl_(std::make_unique<Impl>()) {
  Impl& impl = *impl_;
  impl.path = path;
  impl.program = std::move(ffmpeg);
  impl.width = width;
  impl.height = height;
  if (width <= 0 || height <= 0 || fps <= 0) throw RenderError(path + ": video size and fps must be positive");

  impl.log = std::tmpfile();
  if (impl.log == nullptr)
    throw RenderError(path + ": cannot create a temporary file for ffmpeg's messages: " + std::strerror(errno));
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    std::fclose(impl.log);
    throw RenderError(path + ": cannot create a pipe to ffmpeg: " + std::strerror(errno));
  }
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  const std::vector<std::string> arguments = {
      impl.program, "-hide_banner", "-loglevel", "error", "-y",
      // Input: raw 8-bit RGB frames, top row first, on stdin.
      "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", size, "-framerate", std::to_string(fps), "-i", "pipe:0",
      // yuv420p needs even sides: pad an odd width or height by one pixel.
      "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-an",
      // H.264, visually lossless for flat-shaded pictures, playable everywhere.
      "-c:v", "libx264", "-preset", "fast", "-crf", "18", "-pix_fmt", "yuv420p", "-movflags", "+faststart", path};
  try {
    impl.pid = spawn(arguments, fds[0], ::fileno(impl.log));
  } catch (...) {
    ::close(fds[0]);
    ::close(fds[1]);
    std::fclose(impl.log);
    throw;
  }
  ::close(fds[0]);
  impl.pipe_fd = fds[1];
  impl.previous_sigpipe = std::signal(SIGPIPE, SIG_IGN);
}

VideoWriter::~VideoWriter() {
  Impl& impl = *impl_;
  if (impl.pid > 0) {
    // Not finished: a failed run. Stop ffmpeg; its partial file goes with the partial folder.
    ::kill(impl.pid, SIGKILL);
    if (impl.pipe_fd >= 0) ::close(impl.pipe_fd);
    wait_for(impl.pid);
  }
  if (impl.log != nullptr) std::fclose(impl.log);
  std::signal(SIGPIPE, impl.previous_sigpipe == SIG_ERR ? SIG_DFL : impl.previous_sigpipe);
}

void VideoWriter::write_frame(const Image& image) {
  Impl& impl = *impl_;
  if (impl.pid <= 0) throw RenderError(impl.path + ": write_frame after finish");
  if (image.width != impl.width || image.height != impl.height ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3) {
    throw RenderError(impl.path + ": frame of " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                      " for a " + std::to_string(impl.width) + "x" + std::to_string(impl.height) + " video");
  }
  const std::uint8_t* data = image.rgb.data();
  std::size_t left = image.rgb.size();
  while (left > 0) {
    const ssize_t written = ::write(impl.pipe_fd, data, left);
    if (written < 0) {
      if (errno == EINTR) continue;
      const int error = errno;
      impl.wait_and_check(std::string("writing frame ") + std::to_string(impl.frames) + ": " + std::strerror(error));
    }
    data += written;
    left -= static_cast<std::size_t>(written);
  }
  ++impl.frames;
}

void VideoWriter::finish() {
  Impl& impl = *impl_;
  if (impl.pid <= 0) return;
  impl.wait_and_check("");
}

long VideoWriter::frames() const { return impl_->frames; }

bool VideoWriter::available(const std::string& ffmpeg) {
  try {
    const pid_t pid = spawn({ffmpeg, "-hide_banner", "-version"}, -1, -1);
    const int status = wait_for(pid);
    return status >= 0 && WIFEXITED(status) && WEXITSTATUS(status) == 0;
  } catch (const RenderError&) {
    return false;
  }
}

}  // namespace clothsim::render
