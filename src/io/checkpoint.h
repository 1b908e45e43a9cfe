// Checkpoint files: a StateArchive (core/state_archive.h) on disk, versioned, checksummed and
// written atomically. run_checkpoints.h decides when a run writes them and which one it resumes.
//
// Layout (all integers little-endian, the byte order of every machine clothsim builds for):
//   offset 0   magic, 8 bytes: 0x89 "CSCKPT" '\n' (the 0x89 and the newline catch a file that
//              went through a text-mode copy, as PNG's signature does)
//          8   uint32 format version (kCheckpointVersion)
//         12   uint32 reserved, 0
//         16   uint64 payload length P, bytes
//         24   the payload: one record per field, in the order the archive met them:
//                uint16 name length, the name (UTF-8), uint8 type, uint64 count, the values
//              (count of them: float64, uint64, Vec3 as 3 float64, uint8, uint32, int32, or the
//              bytes of a text)
//     24 + P   uint32 CRC-32 (core/crc32.h) of the payload
// A file is accepted only whole: the right magic and version, a length of exactly 24 + P + 4
// bytes, and a matching checksum. So a file cut short by a crash, or damaged on disk, is refused
// before a single field is applied. A loading archive then checks each record's name, type and
// count against the field asked for, in order: a file of another build's field list fails on the
// first field that differs (the version moves whenever the list changes).
//
// Writing goes to a temporary file beside the target, which is flushed to disk (fsync) and then
// renamed over the target, and the folder is synced: a reader sees the previous file or the whole
// new one, never part of one, even if the process is killed or the machine loses power mid-write.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include "core/state_archive.h"

namespace clothsim {

// 2: the records' fields from their one list (core/record_fields.h): every IntegratorStats field of
// the replaced integrators, the energies in the balance's order, the contact counters' names.
// 3: the precision choice's statistics (sim/precision_choice.h).
inline constexpr std::uint32_t kCheckpointVersion = 3;

// A checkpoint that cannot be read: missing, truncated, damaged, of another version, or not
// fitting the simulation it is applied to. The message names the file and what is wrong.
class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Writes `fill`'s fields to `path` atomically (see the top of the file). Throws std::runtime_error
// naming the path on an I/O failure; `path` is then unchanged and no temporary file is left.
void write_checkpoint(const std::filesystem::path& path, const std::function<void(StateArchive&)>& fill);

// A checkpoint file opened for loading. The constructor verifies the whole file (magic, version,
// length, checksum); the archive then hands out its fields in order.
class CheckpointReader final : public StateArchive {
 public:
  // Throws CheckpointError naming `path` if it cannot be opened or fails a check.
  explicit CheckpointReader(std::filesystem::path path);
  ~CheckpointReader() override;
  CheckpointReader(const CheckpointReader&) = delete;
  CheckpointReader& operator=(const CheckpointReader&) = delete;

  bool loading() const override { return true; }
  void value(std::string_view name, double& x) override;
  void value(std::string_view name, std::uint64_t& x) override;
  void text(std::string_view name, std::string& x) override;
  void array(std::string_view name, std::span<double> x) override;
  void array(std::string_view name, std::span<Vec3> x) override;
  void array(std::string_view name, std::span<std::uint8_t> x) override;
  void array(std::string_view name, std::span<std::uint32_t> x) override;
  void array(std::string_view name, std::span<std::int32_t> x) override;
  void expect_values(std::uint64_t count, std::size_t size) override;
  using StateArchive::value;

  // Throws CheckpointError unless every field of the file has been read.
  void finish() const;
  const std::filesystem::path& path() const { return path_; }

  // The record types of the payload (io/checkpoint.cpp).
  enum class Type : std::uint8_t;

 private:
  // Reads the next record's header and checks it is field `name` of `type` with `count` values
  // (any count when count_known is false); returns its count.
  std::uint64_t next(std::string_view name, Type type, std::uint64_t count, bool count_known);
  void read_bytes(void* buffer, std::uint64_t bytes);
  [[noreturn]] void fail(const std::string& what) const;

  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
  std::uint64_t remaining_ = 0;  // payload bytes not read yet
};

}  // namespace clothsim
