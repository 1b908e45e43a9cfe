// PNG writing and reading through libpng's simplified API (png_image, libpng >= 1.6), which
// handles the format's details and reports errors in a message instead of a longjmp.
#include "render/image.h"

#include <png.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>

namespace clothsim::render {
namespace {

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};

std::runtime_error png_error(const std::string& path, const std::string& what) {
  return std::runtime_error(path + ": " + what);
}

}  // namespace

void write_png(const std::string& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3) {
    throw png_error(path, "write_png: the image is empty or its pixel array does not match its size");
  }
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (file == nullptr) throw png_error(path, std::string("cannot create file: ") + std::strerror(errno));

  png_image header;
  std::memset(&header, 0, sizeof header);
  header.version = PNG_IMAGE_VERSION;
  header.width = static_cast<png_uint_32>(image.width);
  header.height = static_cast<png_uint_32>(image.height);
  header.format = PNG_FORMAT_RGB;
  errno = 0;
  const int ok = png_image_write_to_stdio(&header, file.get(), 0, image.rgb.data(), image.width * 3, nullptr);
  const std::string message = header.message;
  png_image_free(&header);
  if (!ok) throw png_error(path, "PNG write failed: " + message);
  const bool write_failed = std::ferror(file.get()) != 0;
  const int write_error = errno;
  errno = 0;
  const bool closed = std::fclose(file.release()) == 0;
  if (write_failed) throw png_error(path, std::string("write failed: ") + std::strerror(write_error));
  if (!closed) throw png_error(path, std::string("close failed: ") + std::strerror(errno));
}

Image read_png(const std::string& path) {
  png_image header;
  std::memset(&header, 0, sizeof header);
  header.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&header, path.c_str())) {
    throw png_error(path, std::string("cannot read PNG: ") + header.message);
  }
  header.format = PNG_FORMAT_RGB;  // libpng converts (drops alpha against black, expands grey)
  Image image;
  image.width = static_cast<int>(header.width);
  image.height = static_cast<int>(header.height);
  image.rgb.resize(PNG_IMAGE_SIZE(header));
  if (!png_image_finish_read(&header, nullptr, image.rgb.data(), 0, nullptr)) {
    const std::string message = header.message;
    png_image_free(&header);
    throw png_error(path, "cannot read PNG: " + message);
  }
  return image;
}

}  // namespace clothsim::render
