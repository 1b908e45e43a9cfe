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
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>
#include <vector>

#include "core/child_process.h"

namespace clothsim::render {
namespace {

// Starts ffmpeg with stdin from `stdin_fd` and stdout and stderr to `output_fd`, in a process
// group of its own: Ctrl-C in the terminal goes to the terminal's foreground group, and ffmpeg
// would stop (and fail the video) while clothsim finishes the interrupted run.
pid_t spawn_ffmpeg(const std::vector<std::string>& arguments, int stdin_fd, int output_fd) {
  try {
    return spawn_process(arguments, {.stdin_fd = stdin_fd, .output_fd = output_fd, .own_process_group = true});
  } catch (const std::system_error& error) {
    throw RenderError(std::string(error.what()) +
                      (error.code().value() == ENOENT
                           ? " (is ffmpeg installed? install it, or use --render none or --render image)"
                           : ""));
  }
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
    const int status = wait_process(pid);
    pid = -1;
    if (status >= 0 && WIFEXITED(status) && WEXITSTATUS(status) == 0 && context.empty()) return;
    std::string message = path + ": video encoding failed";
    if (!context.empty()) message += " (" + context + ")";
    message += ": " + program + " " + describe_exit_status(status);
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
    impl.pid = spawn_ffmpeg(arguments, fds[0], ::fileno(impl.log));
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
    wait_process(impl.pid);
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
    const pid_t pid = spawn_ffmpeg({ffmpeg, "-hide_banner", "-version"}, -1, -1);
    const int status = wait_process(pid);
    return status >= 0 && WIFEXITED(status) && WEXITSTATUS(status) == 0;
  } catch (const RenderError&) {
    return false;
  }
}

}  // namespace clothsim::render
