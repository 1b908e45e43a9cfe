#include "io/checkpoint.h"

#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <bit>
#include <cerrno>
#include <cstring>
#include <limits>
#include <system_error>
#include <vector>

#include "core/crc32.h"

namespace clothsim {

static_assert(std::endian::native == std::endian::little, "checkpoint files are little-endian, as is the host");
static_assert(sizeof(Vec3) == 3 * sizeof(double), "a Vec3 is stored as its 3 doubles");

enum class CheckpointReader::Type : std::uint8_t {
  f64 = 1,
  u64,
  text,
  f64_array,
  vec3_array,
  u8_array,
  u32_array,
  i32_array
};

namespace {

namespace fs = std::filesystem;
using Type = CheckpointReader::Type;

constexpr std::array<char, 8> kMagic = {'\x89', 'C', 'S', 'C', 'K', 'P', 'T', '\n'};
constexpr std::size_t kHeaderBytes = 24;
constexpr std::size_t kTrailerBytes = 4;
constexpr std::size_t kMaxName = 1024;

std::string system_reason(int error) { return std::error_code(error, std::generic_category()).message(); }

// The saving archive: streams records into a file, the checksum computed on the way.
class CheckpointWriter final : public StateArchive {
 public:
  explicit CheckpointWriter(const fs::path& path) : path_(path) {
    file_ = std::fopen(path.c_str(), "wb");
    if (file_ == nullptr) fail("cannot create file", errno);
    std::array<unsigned char, kHeaderBytes> header{};  // the length is filled in by commit()
    std::memcpy(header.data(), kMagic.data(), kMagic.size());
    std::memcpy(header.data() + 8, &kCheckpointVersion, 4);
    put(header.data(), header.size(), false);
  }
  ~CheckpointWriter() override {
    if (file_ != nullptr) std::fclose(file_);
  }
  CheckpointWriter(const CheckpointWriter&) = delete;
  CheckpointWriter& operator=(const CheckpointWriter&) = delete;

  bool loading() const override { return false; }
  void value(std::string_view name, double& x) override { record(name, Type::f64, &x, 1, sizeof x); }
  void value(std::string_view name, std::uint64_t& x) override { record(name, Type::u64, &x, 1, sizeof x); }
  void text(std::string_view name, std::string& x) override { record(name, Type::text, x.data(), x.size(), 1); }
  void array(std::string_view name, std::span<double> x) override {
    record(name, Type::f64_array, x.data(), x.size(), sizeof(double));
  }
  void array(std::string_view name, std::span<Vec3> x) override {
    record(name, Type::vec3_array, x.data(), x.size(), sizeof(Vec3));
  }
  void array(std::string_view name, std::span<std::uint8_t> x) override {
    record(name, Type::u8_array, x.data(), x.size(), 1);
  }
  void array(std::string_view name, std::span<std::uint32_t> x) override {
    record(name, Type::u32_array, x.data(), x.size(), 4);
  }
  void array(std::string_view name, std::span<std::int32_t> x) override {
    record(name, Type::i32_array, x.data(), x.size(), 4);
  }
  void expect_values(std::uint64_t /*count*/, std::size_t /*size*/) override {}
  using StateArchive::value;

  // Writes the trailer and the payload length, and flushes the file to disk.
  void commit() {
    put(&crc_, sizeof crc_, false);
    if (std::fseek(file_, 16, SEEK_SET) != 0) fail("cannot write file", errno);
    put(&payload_, sizeof payload_, false);
    if (std::fflush(file_) != 0 || ::fsync(::fileno(file_)) != 0) fail("cannot write file", errno);
    const int closed = std::fclose(file_);
    file_ = nullptr;
    if (closed != 0) fail("cannot write file", errno);
  }

 private:
  void record(std::string_view name, Type type, const void* data, std::size_t count, std::size_t size) {
    const auto name_length = static_cast<std::uint16_t>(name.size());
    const auto type_code = static_cast<std::uint8_t>(type);
    const auto stored_count = static_cast<std::uint64_t>(count);
    put(&name_length, sizeof name_length, true);
    put(name.data(), name.size(), true);
    put(&type_code, sizeof type_code, true);
    put(&stored_count, sizeof stored_count, true);
    put(data, count * size, true);
  }
  void put(const void* data, std::size_t bytes, bool payload) {
    if (bytes == 0) return;
    if (std::fwrite(data, 1, bytes, file_) != bytes) fail("cannot write file", errno);
    if (!payload) return;
    crc_ = crc32(data, bytes, crc_);
    payload_ += bytes;
  }
  [[noreturn]] void fail(const char* what, int error) const {
    throw std::runtime_error(path_.string() + ": " + what + ": " + system_reason(error));
  }

  fs::path path_;
  std::FILE* file_ = nullptr;
  std::uint32_t crc_ = 0;
  std::uint64_t payload_ = 0;
};

std::string_view type_name(Type type) {
  switch (type) {
    case Type::f64: return "float64";
    case Type::u64: return "uint64";
    case Type::text: return "text";
    case Type::f64_array: return "float64 array";
    case Type::vec3_array: return "Vec3 array";
    case Type::u8_array: return "uint8 array";
    case Type::u32_array: return "uint32 array";
    case Type::i32_array: return "int32 array";
  }
  return "unknown type";
}

std::size_t value_size(Type type) {
  switch (type) {
    case Type::f64:
    case Type::u64:
    case Type::f64_array: return 8;
    case Type::vec3_array: return sizeof(Vec3);
    case Type::text:
    case Type::u8_array: return 1;
    case Type::u32_array:
    case Type::i32_array: return 4;
  }
  return 0;
}

void sync_folder(const fs::path& folder) {
  const int fd = ::open(folder.empty() ? "." : folder.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;  // best effort: the rename itself is atomic either way
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

void write_checkpoint(const fs::path& path, const std::function<void(StateArchive&)>& fill) {
  fs::path temporary = path.parent_path() / ("." + path.filename().string() + ".tmp-" + std::to_string(::getpid()));
  try {
    CheckpointWriter writer(temporary);
    fill(writer);
    writer.commit();
    fs::rename(temporary, path);
  } catch (...) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw;
  }
  sync_folder(path.parent_path());
}

CheckpointReader::CheckpointReader(fs::path path) : path_(std::move(path)) {
  file_ = std::fopen(path_.c_str(), "rb");
  if (file_ == nullptr) fail("cannot open file: " + system_reason(errno));
  std::array<unsigned char, kHeaderBytes> header{};
  if (std::fread(header.data(), 1, header.size(), file_) != header.size()) {
    fail("truncated: shorter than the 24-byte header");
  }
  if (std::memcmp(header.data(), kMagic.data(), kMagic.size()) != 0) fail("not a clothsim checkpoint (wrong magic)");
  std::uint32_t version = 0;
  std::uint32_t reserved = 0;
  std::uint64_t payload = 0;
  std::memcpy(&version, header.data() + 8, 4);
  std::memcpy(&reserved, header.data() + 12, 4);
  std::memcpy(&payload, header.data() + 16, 8);
  if (version != kCheckpointVersion) {
    fail("format version " + std::to_string(version) + ", but this clothsim reads version " +
         std::to_string(kCheckpointVersion));
  }
  if (reserved != 0) fail("damaged header (reserved field " + std::to_string(reserved) + ", expected 0)");
  std::error_code error;
  const std::uintmax_t size = fs::file_size(path_, error);
  if (error) fail("cannot read its size: " + error.message());
  if (payload > std::numeric_limits<std::uint64_t>::max() - kHeaderBytes - kTrailerBytes ||
      size != kHeaderBytes + payload + kTrailerBytes) {
    fail("truncated or damaged: " + std::to_string(size) + " bytes, but its header promises " +
         (payload > std::numeric_limits<std::uint64_t>::max() - kHeaderBytes - kTrailerBytes
              ? std::string("more than 2^64")
              : std::to_string(kHeaderBytes + payload + kTrailerBytes)));
  }
  // The checksum over the whole payload, before any field is handed out.
  std::vector<unsigned char> buffer(std::size_t{1} << 20);
  std::uint32_t crc = 0;
  for (std::uint64_t left = payload; left > 0;) {
    const std::size_t chunk = static_cast<std::size_t>(std::min<std::uint64_t>(left, buffer.size()));
    if (std::fread(buffer.data(), 1, chunk, file_) != chunk) fail("cannot read file: " + system_reason(errno));
    crc = crc32(buffer.data(), chunk, crc);
    left -= chunk;
  }
  std::uint32_t stored = 0;
  if (std::fread(&stored, 1, sizeof stored, file_) != sizeof stored) fail("cannot read the checksum");
  if (crc != stored) fail("damaged: its checksum does not match its contents");
  if (std::fseek(file_, static_cast<long>(kHeaderBytes), SEEK_SET) != 0)
    fail("cannot read file: " + system_reason(errno));
  remaining_ = payload;
}

CheckpointReader::~CheckpointReader() {
  if (file_ != nullptr) std::fclose(file_);
}

void CheckpointReader::fail(const std::string& what) const { throw CheckpointError(path_.string() + ": " + what); }

void CheckpointReader::read_bytes(void* buffer, std::uint64_t bytes) {
  if (bytes > remaining_) fail("a field runs past the end of the payload");
  if (bytes > 0 && std::fread(buffer, 1, static_cast<std::size_t>(bytes), file_) != bytes) {
    fail("cannot read file: " + system_reason(errno));
  }
  remaining_ -= bytes;
}

std::uint64_t CheckpointReader::next(std::string_view name, Type type, std::uint64_t count, bool count_known) {
  std::uint16_t name_length = 0;
  read_bytes(&name_length, sizeof name_length);
  if (name_length > kMaxName) fail("damaged: a field name of " + std::to_string(name_length) + " bytes");
  std::string stored_name(name_length, '\0');
  read_bytes(stored_name.data(), name_length);
  if (stored_name != name) {
    fail("expected field '" + std::string(name) + "', found '" + stored_name +
         "' (a checkpoint of another clothsim build or another scene)");
  }
  std::uint8_t stored_type = 0;
  read_bytes(&stored_type, sizeof stored_type);
  std::uint64_t stored_count = 0;
  read_bytes(&stored_count, sizeof stored_count);
  if (stored_type != static_cast<std::uint8_t>(type)) {
    fail("field '" + stored_name + "' is stored as type " + std::to_string(stored_type) + ", expected " +
         std::string(type_name(type)));
  }
  if (count_known && stored_count != count) {
    fail("field '" + stored_name + "' has " + std::to_string(stored_count) + " values, but the simulation has " +
         std::to_string(count) + " (a checkpoint of another scene?)");
  }
  if (stored_count > remaining_ / value_size(type))
    fail("field '" + stored_name + "' runs past the end of the payload");
  return stored_count;
}

void CheckpointReader::value(std::string_view name, double& x) {
  next(name, Type::f64, 1, true);
  read_bytes(&x, sizeof x);
}

void CheckpointReader::value(std::string_view name, std::uint64_t& x) {
  next(name, Type::u64, 1, true);
  read_bytes(&x, sizeof x);
}

void CheckpointReader::text(std::string_view name, std::string& x) {
  const std::uint64_t count = next(name, Type::text, 0, false);
  x.assign(static_cast<std::size_t>(count), '\0');
  read_bytes(x.data(), count);
}

void CheckpointReader::array(std::string_view name, std::span<double> x) {
  next(name, Type::f64_array, x.size(), true);
  read_bytes(x.data(), x.size_bytes());
}

void CheckpointReader::array(std::string_view name, std::span<Vec3> x) {
  next(name, Type::vec3_array, x.size(), true);
  read_bytes(x.data(), x.size_bytes());
}

void CheckpointReader::array(std::string_view name, std::span<std::uint8_t> x) {
  next(name, Type::u8_array, x.size(), true);
  read_bytes(x.data(), x.size_bytes());
}

void CheckpointReader::array(std::string_view name, std::span<std::uint32_t> x) {
  next(name, Type::u32_array, x.size(), true);
  read_bytes(x.data(), x.size_bytes());
}

void CheckpointReader::array(std::string_view name, std::span<std::int32_t> x) {
  next(name, Type::i32_array, x.size(), true);
  read_bytes(x.data(), x.size_bytes());
}

void CheckpointReader::expect_values(std::uint64_t count, std::size_t size) {
  if (size > 0 && count > remaining_ / size) fail("damaged: a list longer than the rest of the file");
}

void CheckpointReader::finish() const {
  if (remaining_ != 0)
    fail(std::to_string(remaining_) + " bytes of fields left unread (a checkpoint of another build?)");
}

}  // namespace clothsim
