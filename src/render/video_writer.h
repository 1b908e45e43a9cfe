// H.264 video through the ffmpeg program: raw RGB frames are piped to
//   ffmpeg -f rawvideo -pix_fmt rgb24 -s WxH -r FPS -i - -c:v libx264 -pix_fmt yuv420p ... out.mp4
// Running the program (rather than linking libavcodec) keeps a large, fast-moving API out of the
// build, and ffmpeg is on every machine that plays video. yuv420p is what browsers and players
// expect; it needs even width and height, so odd sizes are padded by one pixel (ffmpeg's pad
// filter), never rejected.
#pragma once

#include <memory>
#include <string>

#include "render/image.h"
#include "render/render_error.h"

namespace clothsim::render {

class VideoWriter {
 public:
  // Starts ffmpeg writing `path` (overwritten). Throws RenderError if ffmpeg cannot be started
  // (e.g. not installed: the message says so).
  VideoWriter(const std::string& path, int width, int height, int fps, std::string ffmpeg = "ffmpeg");
  // Kills ffmpeg if finish() was not called (a run that failed on the way).
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // Sends one frame (image.width/height must match). Throws RenderError if ffmpeg has died (its
  // stderr is in the message).
  void write_frame(const Image& image);
  // Closes the pipe, waits for ffmpeg and throws RenderError with its stderr unless it exited 0.
  void finish();

  long frames() const;

  // Whether `ffmpeg` can be run (`ffmpeg -version` exits 0).
  static bool available(const std::string& ffmpeg = "ffmpeg");

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clothsim::render
