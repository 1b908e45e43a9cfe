// The PC2 writer; the format is described in pc2.h.
//
// Values are written as the host's bytes, which is the format's little-endian int32 and IEEE-754
// float32 only on such a host; the static_asserts make any other host a compile error rather
// than a silently wrong file (as in io/npy.cpp).
#include "io/pc2.h"

#include <bit>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <system_error>

#include "io/file_writing.h"

namespace clothsim {
namespace {

static_assert(std::endian::native == std::endian::little, "PC2 stores little-endian values as host bytes");
static_assert(std::numeric_limits<float>::is_iec559 && sizeof(float) == 4, "PC2 floats are IEEE-754 binary32");

// Byte offset of the sample count in the header.
constexpr long kSampleCountOffset = 28;

void write_bytes(std::FILE* file, const void* data, std::size_t size, const std::string& path) {
  if (std::fwrite(data, 1, size, file) != size) throw io_error(path, "cannot write file", errno);
}

}  // namespace

Pc2Writer::Pc2Writer(std::string path, std::size_t point_count, float start_frame, float sample_rate)
    : path_(std::move(path)), point_count_(point_count), buffer_(3 * point_count) {
  if (point_count > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw io_error(path_, "too many points for a PC2 file (" + std::to_string(point_count) + ")", 0);
  }
  file_ = std::fopen(path_.c_str(), "wb");
  if (file_ == nullptr) throw io_error(path_, "cannot create file", errno);
  const std::int32_t points = static_cast<std::int32_t>(point_count);
  const std::int32_t no_samples = 0;
  write_bytes(file_, kMagic, sizeof(kMagic), path_);
  write_bytes(file_, &kVersion, sizeof(kVersion), path_);
  write_bytes(file_, &points, sizeof(points), path_);
  write_bytes(file_, &start_frame, sizeof(start_frame), path_);
  write_bytes(file_, &sample_rate, sizeof(sample_rate), path_);
  write_bytes(file_, &no_samples, sizeof(no_samples), path_);
}

Pc2Writer::Pc2Writer(std::string path, std::size_t point_count, std::size_t samples)
    : path_(std::move(path)), point_count_(point_count), samples_(samples), buffer_(3 * point_count) {
  file_ = std::fopen(path_.c_str(), "r+b");
  if (file_ == nullptr) throw io_error(path_, "cannot reopen", errno);
  char magic[sizeof(kMagic)] = {};
  std::int32_t version = 0;
  std::int32_t points = 0;
  if (std::fread(magic, 1, sizeof magic, file_) != sizeof magic || std::memcmp(magic, kMagic, sizeof magic) != 0 ||
      std::fread(&version, sizeof version, 1, file_) != 1 || version != kVersion ||
      std::fread(&points, sizeof points, 1, file_) != 1 || points < 0 ||
      static_cast<std::size_t>(points) != point_count) {
    throw io_error(path_, "not a point cache of " + std::to_string(point_count) + " points", 0);
  }
  const std::uintmax_t keep = kHeaderBytes + static_cast<std::uintmax_t>(samples) * point_count * 3 * sizeof(float);
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(path_, error);
  if (error || size < keep) throw io_error(path_, "holds fewer than " + std::to_string(samples) + " samples", 0);
  std::filesystem::resize_file(path_, keep, error);
  if (error) throw io_error(path_, "cannot cut off the later samples: " + error.message(), 0);
  if (std::fseek(file_, 0, SEEK_END) != 0) throw io_error(path_, "cannot seek", errno);
}

Pc2Writer::~Pc2Writer() {
  if (file_ != nullptr) std::fclose(file_);
}

void Pc2Writer::append(std::span<const Vec3> position) {
  if (position.size() != point_count_) {
    throw io_error(
        path_,
        "a sample of " + std::to_string(position.size()) + " points for a cache of " + std::to_string(point_count_), 0);
  }
  for (std::size_t p = 0; p < point_count_; ++p) {
    buffer_[3 * p] = static_cast<float>(position[p].x);
    buffer_[3 * p + 1] = static_cast<float>(position[p].y);
    buffer_[3 * p + 2] = static_cast<float>(position[p].z);
  }
  write_bytes(file_, buffer_.data(), buffer_.size() * sizeof(float), path_);
  ++samples_;
}

void Pc2Writer::flush() {
  if (file_ != nullptr && std::fflush(file_) != 0) throw io_error(path_, "cannot write file", errno);
}

void Pc2Writer::close() {
  if (file_ == nullptr) return;
  if (samples_ > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw io_error(path_, "too many samples for a PC2 file (" + std::to_string(samples_) + ")", 0);
  }
  const std::int32_t samples = static_cast<std::int32_t>(samples_);
  if (std::fseek(file_, kSampleCountOffset, SEEK_SET) != 0) throw io_error(path_, "cannot seek", errno);
  write_bytes(file_, &samples, sizeof(samples), path_);
  std::FILE* file = file_;
  file_ = nullptr;
  if (std::fclose(file) != 0) throw io_error(path_, "cannot close file", errno);
}

}  // namespace clothsim
