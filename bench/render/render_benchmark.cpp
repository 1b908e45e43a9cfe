// Render time per frame of `clothsim run`'s pictures, for square sheets of 50, 100 and 200
// particles a side, headless (render/headless.h) at 1280x720 with 4x MSAA by default
// (--size WxH, --samples N, --no-ground to see what the parts cost).
//
// Each sheet is given a smooth two-wave shape (so normals vary and no triangle is degenerate),
// framed by Camera::fit, and drawn `frames` times after 3 warm-up frames. Per frame it times
//   draw     Renderer::draw (CPU mesh and normals, upload, GL calls) plus glFinish, i.e. until
//            the GPU (or llvmpipe) is done;
//   readback HeadlessContext::read (MSAA resolve, glReadPixels, row flip);
// and reports the median of each and of their sum, in milliseconds. It then pipes `frames`
// frames to ffmpeg (VideoWriter) and reports the encoding cost per frame (total / frames:
// ffmpeg works in its own process, so single frames cannot be timed).
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "model/cloth_model.h"
#include "render/camera.h"
#include "render/headless.h"
#include "render/renderer.h"
#include "render/video_writer.h"

namespace {

using clothsim::Vec3;
using Clock = std::chrono::steady_clock;

double milliseconds_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  int width = 1280;
  int height = 720;
  int frames = 15;
  int samples = 4;
  bool ground = true;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    const bool has_value = i + 1 < argc;
    if (flag == "--no-ground") {
      ground = false;
      continue;
    }
    if (has_value && flag == "--size" && std::sscanf(argv[++i], "%dx%d", &width, &height) == 2) continue;
    if (has_value && flag == "--frames") {
      frames = std::max(1, std::atoi(argv[++i]));
      continue;
    }
    if (has_value && flag == "--samples") {
      samples = std::max(1, std::atoi(argv[++i]));
      continue;
    }
    std::fprintf(stderr, "usage: render_benchmark [--size WxH] [--frames N] [--samples N] [--no-ground]\n");
    return 2;
  }

  clothsim::render::HeadlessContext context(width, height, samples);
  clothsim::render::Renderer renderer;
  std::printf("render_benchmark: %dx%d, %d frames per sheet after 3 warm-up frames\n%s\n\n", width, height, frames,
              context.description().c_str());
  std::printf("%-9s %9s %10s %12s %10s %12s\n", "sheet", "triangles", "draw ms", "readback ms", "total ms",
              "encode ms");
  clothsim::render::Image image;
  for (const int side : {50, 100, 200}) {
    clothsim::LatticeDef lattice;
    lattice.rows = side;
    lattice.cols = side;
    lattice.spacing = 10.0 / side;
    const clothsim::ClothModel model = clothsim::build_lattice(lattice, clothsim::Environment{}, {});
    std::vector<Vec3> position = model.particle_rest_position;
    for (Vec3& p : position) p.y = 0.8 * std::sin(0.9 * p.x) * std::cos(0.6 * p.z);
    clothsim::render::Camera camera;
    camera.fit(position, static_cast<double>(width) / height);
    clothsim::render::RenderOptions options;
    options.show_ground = ground;

    std::vector<double> draw_times;
    std::vector<double> read_times;
    std::vector<double> totals;
    for (int frame = -3; frame < frames; ++frame) {
      context.bind();
      const Clock::time_point start = Clock::now();
      renderer.draw(model, position, options, camera, width, height);
      glFinish();
      const double draw = milliseconds_since(start);
      const Clock::time_point read_start = Clock::now();
      context.read(image);
      const double read = milliseconds_since(read_start);
      if (frame < 0) continue;
      draw_times.push_back(draw);
      read_times.push_back(read);
      totals.push_back(draw + read);
    }

    const std::filesystem::path video = std::filesystem::temp_directory_path() / "clothsim_render_benchmark.mp4";
    const Clock::time_point encode_start = Clock::now();
    {
      clothsim::render::VideoWriter writer(video.string(), width, height, 60);
      for (int frame = 0; frame < frames; ++frame) writer.write_frame(image);
      writer.finish();
    }
    const double encode = milliseconds_since(encode_start) / frames;
    std::filesystem::remove(video);

    const std::string name = std::to_string(side) + "x" + std::to_string(side);
    std::printf("%-9s %9d %10.1f %12.1f %10.1f %12.1f\n", name.c_str(), 2 * (side - 1) * (side - 1), median(draw_times),
                median(read_times), median(totals), encode);
  }
  return 0;
}
