// An 8-bit RGB image in memory, and its PNG writer.
//
// Rows run top to bottom (the order of PNG files and of video frames); OpenGL reads bottom to
// top, so HeadlessContext::read flips. PNG goes through libpng: it reports write errors (ENOSPC
// through fwrite) where stb_image_write's one-call API returns only a bool, and Debian ships it
// as a shared library every desktop already has.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace clothsim::render {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // [height * width * 3], row-major, top row first

  const std::uint8_t* pixel(int x, int y) const { return &rgb[(static_cast<std::size_t>(y) * width + x) * 3]; }
};

// Writes `image` as an 8-bit RGB PNG to `path` (created or truncated). Throws std::runtime_error
// naming the path and the reason.
void write_png(const std::string& path, const Image& image);

// Reads an 8-bit RGB or RGBA PNG (tests and tools); alpha is dropped. Throws std::runtime_error.
Image read_png(const std::string& path);

}  // namespace clothsim::render
