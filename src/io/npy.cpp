// .npy writing and reading; the format and the design are described in npy.h.
//
// All I/O goes through stdio: fwrite of whole frames into a large stdio buffer is as fast as the
// disk, and stdio reports failures through errno, which the messages quote. Values are written as
// the host's bytes, which is the '<f8' of the header only on a little-endian IEEE-754 host; the
// static_asserts make any other host a compile error rather than a silently wrong file.
#include "io/npy.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <utility>

#include "core/assert.h"
#include "io/file_writing.h"

namespace clothsim {
namespace {

static_assert(std::endian::native == std::endian::little, "the .npy writer stores doubles as '<f8' host bytes");
static_assert(std::numeric_limits<double>::is_iec559 && sizeof(double) == 8, "'<f8' is IEEE-754 binary64");
// append(span<const Vec3>) writes the Vec3 array as it lies in memory: three packed doubles each.
static_assert(sizeof(Vec3) == 3 * sizeof(double) && std::is_standard_layout_v<Vec3>, "Vec3 must be 3 packed doubles");

constexpr char kMagic[] = "\x93NUMPY";
constexpr std::size_t kMagicBytes = 6;
// Magic, two version bytes and the header length (uint16 in version 1.0, uint32 in 2.0).
constexpr std::size_t kPreambleBytes_v1 = kMagicBytes + 2 + 2;
// The format asks that magic + header end on a multiple of 64 bytes, so the data can be mapped
// aligned (numpy.load(mmap_mode=...)).
constexpr std::size_t kAlignment = 64;
// A 1.0 header longer than this cannot be stored; 2.0 would allow 4 GiB. Ours are ~128 bytes.
constexpr std::size_t kMaxHeaderLength_v1 = 65535;
// Refuse to allocate for absurd header lengths from a corrupt 2.0 file; numpy's own limit is 10000.
constexpr std::size_t kMaxHeaderLengthRead = std::size_t{1} << 20;
// stdio buffer for the streamed writer: frames of small sheets are a few kB, so this batches
// many frames per write(2); frames larger than the buffer go straight through.
constexpr std::size_t kWriteBufferBytes = std::size_t{1} << 18;

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};
using FilePointer = std::unique_ptr<std::FILE, FileCloser>;

std::string shape_text(std::span<const std::size_t> shape) {
  std::string text = "(";
  for (std::size_t axis = 0; axis < shape.size(); ++axis) {
    if (axis > 0) text += ", ";
    text += std::to_string(shape[axis]);
  }
  if (shape.size() == 1) text += ",";  // Python's 1-tuple
  return text + ")";
}

// Product of the extents, or false on size_t overflow.
bool element_count(std::span<const std::size_t> shape, std::size_t& count) {
  count = 1;
  for (const std::size_t extent : shape) {
    if (extent != 0 && count > std::numeric_limits<std::size_t>::max() / extent) return false;
    count *= extent;
  }
  return true;
}

// Magic, version 1.0, header length and the dict padded with spaces to `total_bytes` (or to the
// next multiple of 64 when that is smaller than the minimum), ending in '\n'. Returns an empty
// string when the header would not fit a version 1.0 length field.
std::string make_header(std::span<const std::size_t> shape, std::size_t total_bytes = 0,
                        std::string_view descr = "<f8") {
  const std::string dict =
      "{'descr': '" + std::string(descr) + "', 'fortran_order': False, 'shape': " + shape_text(shape) + ", }";
  const std::size_t minimum = kPreambleBytes_v1 + dict.size() + 1;  // + '\n'
  const std::size_t aligned = (minimum + kAlignment - 1) / kAlignment * kAlignment;
  const std::size_t total = std::max(total_bytes, aligned);
  CLOTHSIM_ASSERT(total % kAlignment == 0, "npy header sizes are multiples of 64");
  const std::size_t header_length = total - kPreambleBytes_v1;
  if (header_length > kMaxHeaderLength_v1) return {};

  std::string header(kMagic, kMagicBytes);
  header += '\x01';  // major version
  header += '\x00';  // minor version
  header += static_cast<char>(header_length & 0xffu);
  header += static_cast<char>((header_length >> 8) & 0xffu);
  header += dict;
  header.append(total - header.size() - 1, ' ');
  header += '\n';
  return header;
}

// Writes `header` at the start of the file and returns to the end; false with errno set on failure.
bool write_header_at_start(std::FILE* file, const std::string& header) {
  errno = 0;
  return std::fseek(file, 0, SEEK_SET) == 0 && std::fwrite(header.data(), 1, header.size(), file) == header.size() &&
         std::fseek(file, 0, SEEK_END) == 0;
}

// A recursive-descent reader for the header dict, a Python literal such as
//   {'descr': '<f8', 'fortran_order': False, 'shape': (3, 4), }
// It accepts exactly what numpy.save writes and numpy.load accepts: the three keys, any order,
// either quote, an optional trailing comma, and a tuple of non-negative integers for the shape.
class HeaderParser {
 public:
  HeaderParser(std::string_view text, const std::string& path) : text_(text), path_(path) {}

  void parse(std::string& descr, bool& fortran_order, std::vector<std::size_t>& shape) {
    bool has_descr = false;
    bool has_fortran_order = false;
    bool has_shape = false;
    skip_space();
    expect('{');
    while (true) {
      skip_space();
      if (consume('}')) break;
      const std::string key = parse_string();
      skip_space();
      expect(':');
      skip_space();
      if (key == "descr" && !has_descr) {
        descr = parse_string();
        has_descr = true;
      } else if (key == "fortran_order" && !has_fortran_order) {
        fortran_order = parse_bool();
        has_fortran_order = true;
      } else if (key == "shape" && !has_shape) {
        shape = parse_shape();
        has_shape = true;
      } else {
        fail("unexpected or repeated key '" + key + "'");
      }
      skip_space();
      if (consume('}')) break;
      expect(',');
    }
    skip_space();
    if (position_ != text_.size()) fail("text after the closing '}'");
    if (!has_descr || !has_fortran_order || !has_shape) {
      fail("the keys 'descr', 'fortran_order' and 'shape' are all required");
    }
  }

 private:
  void skip_space() {
    while (position_ < text_.size() && (text_[position_] == ' ' || text_[position_] == '\n' ||
                                        text_[position_] == '\t' || text_[position_] == '\r')) {
      ++position_;
    }
  }

  bool consume(char expected) {
    if (position_ < text_.size() && text_[position_] == expected) {
      ++position_;
      return true;
    }
    return false;
  }

  void expect(char expected) {
    if (!consume(expected)) fail(std::string("expected '") + expected + "'");
  }

  std::string parse_string() {
    if (position_ >= text_.size() || (text_[position_] != '\'' && text_[position_] != '"')) fail("expected a string");
    const char quote = text_[position_++];
    const std::size_t end = text_.find(quote, position_);
    if (end == std::string_view::npos) fail("unterminated string");
    std::string value(text_.substr(position_, end - position_));
    position_ = end + 1;
    return value;
  }

  bool parse_bool() {
    if (text_.substr(position_).starts_with("True")) {
      position_ += 4;
      return true;
    }
    if (text_.substr(position_).starts_with("False")) {
      position_ += 5;
      return false;
    }
    fail("expected True or False");
  }

  std::vector<std::size_t> parse_shape() {
    std::vector<std::size_t> shape;
    expect('(');
    skip_space();
    if (consume(')')) return shape;  // () is a 0-d array
    bool trailing_comma = false;
    while (true) {
      shape.push_back(parse_extent());
      skip_space();
      trailing_comma = consume(',');
      skip_space();
      if (consume(')')) break;
      if (!trailing_comma) fail("expected ',' or ')' in the shape");
    }
    // (5) is the integer 5 in Python, not a tuple; numpy rejects it too.
    if (shape.size() == 1 && !trailing_comma) fail("a 1-d shape must be written (n,)");
    return shape;
  }

  std::size_t parse_extent() {
    const std::size_t start = position_;
    std::size_t value = 0;
    while (position_ < text_.size() && text_[position_] >= '0' && text_[position_] <= '9') {
      const auto digit = static_cast<std::size_t>(text_[position_] - '0');
      if (value > (std::numeric_limits<std::size_t>::max() - digit) / 10) fail("shape extent overflows 64 bits");
      value = value * 10 + digit;
      ++position_;
    }
    if (position_ == start) fail("expected a non-negative integer in the shape");
    consume('L');  // Python 2 long literals, as in files written by old numpy versions
    return value;
  }

  [[noreturn]] void fail(const std::string& what) const {
    std::string_view shown = text_;
    while (!shown.empty() && (shown.back() == ' ' || shown.back() == '\n')) shown.remove_suffix(1);
    throw std::runtime_error(path_ + ": malformed .npy header (" + what + " at offset " + std::to_string(position_) +
                             "): " + std::string(shown));
  }

  std::string_view text_;
  const std::string& path_;
  std::size_t position_ = 0;
};

}  // namespace

NpyWriter::NpyWriter(std::string path, std::size_t items, std::size_t components)
    : path_(std::move(path)), items_(items), components_(components) {
  std::size_t frame_values = 0;
  const std::array<std::size_t, 2> frame_shape = {items_, components_};
  if (!element_count(frame_shape, frame_values) || frame_values > std::numeric_limits<std::size_t>::max() / 8) {
    throw io_error(path_, "frame size " + shape_text(frame_shape) + " is too large", 0);
  }
  // Reserve the header for the widest frame count, 2^64 - 1 (20 digits), so that close() can
  // rewrite it in place whatever the count turns out to be.
  const std::array<std::size_t, 3> widest = {std::numeric_limits<std::size_t>::max(), items_, components_};
  header_bytes_ = make_header(widest).size();
  if (header_bytes_ == 0) throw io_error(path_, "header too long", 0);

  file_ = std::fopen(path_.c_str(), "wb");
  if (file_ == nullptr) throw io_error(path_, "cannot create file", errno);
  std::setvbuf(file_, nullptr, _IOFBF, kWriteBufferBytes);
  // The provisional header (0 frames) goes into the buffer with the first frames; a full disk
  // shows at the first flush of the buffer.
  const std::array<std::size_t, 3> shape = {0, items_, components_};
  const std::string header = make_header(shape, header_bytes_);
  errno = 0;
  if (std::fwrite(header.data(), 1, header.size(), file_) != header.size()) {
    const int error_number = errno;
    std::fclose(std::exchange(file_, nullptr));
    throw io_error(path_, "cannot write the header", error_number);
  }
}

NpyWriter::NpyWriter(std::string path, std::size_t items, std::size_t components, std::size_t frames)
    : path_(std::move(path)), items_(items), components_(components), frames_(frames) {
  const std::array<std::size_t, 3> widest = {std::numeric_limits<std::size_t>::max(), items_, components_};
  header_bytes_ = make_header(widest).size();
  if (header_bytes_ == 0) throw io_error(path_, "header too long", 0);
  const std::uintmax_t keep = header_bytes_ + static_cast<std::uintmax_t>(frames) * items * components * sizeof(double);
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(path_, error);
  if (error) throw io_error(path_, "cannot reopen: " + error.message(), 0);
  if (size < keep) {
    throw io_error(path_,
                   "holds " + std::to_string(size) + " bytes, fewer than the " + std::to_string(keep) + " of " +
                       std::to_string(frames) + " frames",
                   0);
  }
  std::filesystem::resize_file(path_, keep, error);
  if (error) throw io_error(path_, "cannot cut off the later frames: " + error.message(), 0);
  file_ = std::fopen(path_.c_str(), "r+b");
  if (file_ == nullptr) throw io_error(path_, "cannot reopen", errno);
  std::setvbuf(file_, nullptr, _IOFBF, kWriteBufferBytes);
  write_header();  // the frame count, and the position at the end
}

NpyWriter::~NpyWriter() {
  try {
    close();
  } catch (...) {  // NOLINT(bugprone-empty-catch): a destructor must not throw; see npy.h
  }
}

NpyWriter::NpyWriter(NpyWriter&& other) noexcept
    : path_(std::move(other.path_)),
      file_(std::exchange(other.file_, nullptr)),
      items_(other.items_),
      components_(other.components_),
      frames_(other.frames_),
      header_bytes_(other.header_bytes_),
      failed_(other.failed_) {}

NpyWriter& NpyWriter::operator=(NpyWriter&& other) noexcept {
  if (this != &other) {
    try {
      close();
    } catch (...) {  // NOLINT(bugprone-empty-catch): as in the destructor
    }
    path_ = std::move(other.path_);
    file_ = std::exchange(other.file_, nullptr);
    items_ = other.items_;
    components_ = other.components_;
    frames_ = other.frames_;
    header_bytes_ = other.header_bytes_;
    failed_ = other.failed_;
  }
  return *this;
}

void NpyWriter::append(std::span<const Vec3> frame) {
  if (components_ != 3) {
    throw io_error(path_, "append(Vec3 frame) needs 3 components per item, the file has " + std::to_string(components_),
                   0);
  }
  check_frame(frame.size(), "points", items_);
  write_values(frame.data(), 3 * frame.size());
}

void NpyWriter::append(std::span<const double> frame) {
  check_frame(frame.size(), "values", items_ * components_);
  write_values(frame.data(), frame.size());
}

void NpyWriter::check_frame(std::size_t size, const char* unit, std::size_t expected) const {
  if (file_ == nullptr) throw io_error(path_, "append after close", 0);
  if (failed_) throw io_error(path_, "append after an earlier write failure", 0);
  if (size != expected) {
    throw io_error(path_,
                   "frame has " + std::to_string(size) + " " + unit + ", expected " + std::to_string(expected) +
                       " (items " + std::to_string(items_) + ", components " + std::to_string(components_) + ")",
                   0);
  }
}

void NpyWriter::write_values(const void* values, std::size_t count) {
  errno = 0;
  if (count > 0 && std::fwrite(values, sizeof(double), count, file_) != count) {
    // Part of the frame may be on disk: later frames would land at the wrong offset, so refuse
    // them. The header still names only the complete frames, so the file stays readable.
    failed_ = true;
    throw io_error(path_, "write failed after " + std::to_string(frames_) + " frames", errno);
  }
  ++frames_;
}

void NpyWriter::write_header() {
  const std::array<std::size_t, 3> shape = {frames_, items_, components_};
  const std::string header = make_header(shape, header_bytes_);
  CLOTHSIM_ASSERT(header.size() == header_bytes_, "the reserved header holds any frame count");
  if (!write_header_at_start(file_, header)) throw io_error(path_, "cannot write the header", errno);
}

void NpyWriter::flush() {
  if (file_ == nullptr) return;
  write_header();
  errno = 0;
  if (std::fflush(file_) != 0) throw io_error(path_, "flush failed", errno);
}

void NpyWriter::close() {
  if (file_ == nullptr) return;
  std::FILE* file = std::exchange(file_, nullptr);
  const std::array<std::size_t, 3> shape = {frames_, items_, components_};
  const bool header_written = write_header_at_start(file, make_header(shape, header_bytes_));
  const int header_error = errno;
  errno = 0;
  // fclose flushes the buffered frames; its failure (a full disk, say) loses data too.
  const bool closed = std::fclose(file) == 0;
  if (!header_written) throw io_error(path_, "cannot write the header", header_error);
  if (!closed) throw io_error(path_, "close failed", errno);
}

void write_npy(const std::string& path, std::span<const double> data, std::span<const std::size_t> shape) {
  std::size_t count = 0;
  if (!element_count(shape, count) || count != data.size()) {
    throw io_error(path, "write_npy: " + std::to_string(data.size()) + " values do not fill shape " + shape_text(shape),
                   0);
  }
  const std::string header = make_header(shape);
  if (header.empty()) throw io_error(path, "write_npy: header too long for shape " + shape_text(shape), 0);

  FilePointer file(std::fopen(path.c_str(), "wb"));
  if (file == nullptr) throw io_error(path, "cannot create file", errno);
  errno = 0;
  if (std::fwrite(header.data(), 1, header.size(), file.get()) != header.size() ||
      (count > 0 && std::fwrite(data.data(), sizeof(double), count, file.get()) != count)) {
    throw io_error(path, "write failed", errno);
  }
  errno = 0;
  if (std::fclose(file.release()) != 0) throw io_error(path, "close failed", errno);
}

void write_npy(const std::string& path, std::span<const std::int32_t> data, std::span<const std::size_t> shape) {
  std::size_t count = 0;
  if (!element_count(shape, count) || count != data.size()) {
    throw io_error(path, "write_npy: " + std::to_string(data.size()) + " values do not fill shape " + shape_text(shape),
                   0);
  }
  const std::string header = make_header(shape, 0, "<i4");
  if (header.empty()) throw io_error(path, "write_npy: header too long for shape " + shape_text(shape), 0);

  FilePointer file(std::fopen(path.c_str(), "wb"));
  if (file == nullptr) throw io_error(path, "cannot create file", errno);
  errno = 0;
  if (std::fwrite(header.data(), 1, header.size(), file.get()) != header.size() ||
      (count > 0 && std::fwrite(data.data(), sizeof(std::int32_t), count, file.get()) != count)) {
    throw io_error(path, "write failed", errno);
  }
  errno = 0;
  if (std::fclose(file.release()) != 0) throw io_error(path, "close failed", errno);
}

namespace {

// A file's preamble and header dict, read and checked; the file is left at the data.
struct ParsedHeader {
  std::vector<std::size_t> shape;
  std::string descr;  // "<f8" or "<i4"
  std::size_t value_bytes = 0;
  std::size_t data_offset = 0;  // bytes
};

ParsedHeader read_header(std::FILE* file, const std::string& path) {
  const auto read_exactly = [&](void* buffer, std::size_t bytes, const char* what) {
    errno = 0;
    if (std::fread(buffer, 1, bytes, file) != bytes) {
      throw io_error(path, std::string("truncated .npy file: cannot read the ") + what,
                     std::ferror(file) != 0 ? errno : 0);
    }
  };

  std::array<unsigned char, kMagicBytes + 2> preamble{};
  read_exactly(preamble.data(), preamble.size(), "magic string");
  if (std::memcmp(preamble.data(), kMagic, kMagicBytes) != 0) {
    throw io_error(path, "not a .npy file (it does not start with \\x93NUMPY)", 0);
  }
  const unsigned major = preamble[kMagicBytes];
  const unsigned minor = preamble[kMagicBytes + 1];
  if ((major != 1 && major != 2) || minor != 0) {
    throw io_error(path,
                   ".npy format version " + std::to_string(major) + "." + std::to_string(minor) +
                       " is not supported (1.0 and 2.0 are)",
                   0);
  }
  // Header length: little-endian uint16 in 1.0, uint32 in 2.0.
  std::array<unsigned char, 4> length_bytes{};
  const std::size_t length_size = major == 1 ? 2 : 4;
  read_exactly(length_bytes.data(), length_size, "header length");
  std::size_t header_length = 0;
  for (std::size_t byte = length_size; byte-- > 0;) header_length = (header_length << 8) | length_bytes[byte];
  if (header_length > kMaxHeaderLengthRead) {
    throw io_error(path, "implausible .npy header length " + std::to_string(header_length), 0);
  }
  std::string header(header_length, '\0');
  read_exactly(header.data(), header_length, "header");

  ParsedHeader parsed;
  bool fortran_order = false;
  HeaderParser(header, path).parse(parsed.descr, fortran_order, parsed.shape);
  if (parsed.descr != "<f8" && parsed.descr != "<i4") {
    throw io_error(path,
                   "dtype '" + parsed.descr +
                       "' is not supported: read_npy reads little-endian float64 ('<f8') and int32 ('<i4') only",
                   0);
  }
  parsed.value_bytes = parsed.descr == "<f8" ? sizeof(double) : sizeof(std::int32_t);
  if (fortran_order) throw io_error(path, "Fortran-order arrays are not supported (C order only)", 0);
  parsed.data_offset = length_size + preamble.size() + header_length;
  return parsed;
}

}  // namespace

NpyArray read_npy(const std::string& path) {
  FilePointer file(std::fopen(path.c_str(), "rb"));
  if (file == nullptr) throw io_error(path, "cannot open file", errno);
  const auto read_exactly = [&](void* buffer, std::size_t bytes, const char* what) {
    errno = 0;
    if (std::fread(buffer, 1, bytes, file.get()) != bytes) {
      throw io_error(path, std::string("truncated .npy file: cannot read the ") + what,
                     std::ferror(file.get()) != 0 ? errno : 0);
    }
  };
  ParsedHeader header = read_header(file.get(), path);
  NpyArray array;
  array.shape = std::move(header.shape);
  const std::size_t value_bytes = header.value_bytes;
  const std::size_t data_offset = header.data_offset;

  std::size_t count = 0;
  if (!element_count(array.shape, count) || count > std::numeric_limits<std::size_t>::max() / sizeof(double)) {
    throw io_error(path, "shape " + shape_text(array.shape) + " is too large", 0);
  }
  // Check the size before allocating, so a corrupt shape gives a message, not std::bad_alloc.
  std::error_code error;
  const std::uintmax_t file_bytes = std::filesystem::file_size(path, error);
  if (error) throw io_error(path, "cannot determine the file size: " + error.message(), 0);
  const std::uintmax_t data_bytes = file_bytes >= data_offset ? file_bytes - data_offset : 0;
  if (data_bytes < count * value_bytes) {
    throw io_error(path,
                   "truncated .npy file: shape " + shape_text(array.shape) + " needs " +
                       std::to_string(count * value_bytes) + " data bytes, the file has " + std::to_string(data_bytes),
                   0);
  }
  array.data.resize(count);
  if (value_bytes == sizeof(double)) {
    read_exactly(array.data.data(), count * sizeof(double), "data");
  } else {
    std::vector<std::int32_t> values(count);
    read_exactly(values.data(), count * sizeof(std::int32_t), "data");
    std::copy(values.begin(), values.end(), array.data.begin());
  }
  return array;
}

void read_npy_frame(const std::string& path, std::size_t frame, std::span<Vec3> out) {
  FilePointer file(std::fopen(path.c_str(), "rb"));
  if (file == nullptr) throw io_error(path, "cannot open file", errno);
  const ParsedHeader header = read_header(file.get(), path);
  if (header.descr != "<f8" || header.shape.size() != 3 || header.shape[1] != out.size() || header.shape[2] != 3) {
    throw io_error(path,
                   "expected float64 frames of shape (" + std::to_string(out.size()) + ", 3), found " + header.descr +
                       " " + shape_text(header.shape),
                   0);
  }
  const std::uintmax_t offset = header.data_offset + static_cast<std::uintmax_t>(frame) * out.size_bytes();
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (error || size < offset + out.size_bytes()) throw io_error(path, "has no frame " + std::to_string(frame), 0);
  errno = 0;
  if (std::fseek(file.get(), static_cast<long>(offset), SEEK_SET) != 0 ||
      std::fread(out.data(), 1, out.size_bytes(), file.get()) != out.size_bytes()) {
    throw io_error(path, "cannot read frame " + std::to_string(frame), errno);
  }
}

}  // namespace clothsim
