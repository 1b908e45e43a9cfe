// NumPy .npy files: the trajectory output format, and a reader for tests and tools.
//
// Format: https://numpy.org/doc/stable/reference/generated/numpy.lib.format.html (version 1.0).
// A file is the magic "\x93NUMPY", a version (1, 0), a little-endian uint16 header length, then an
// ASCII Python dict literal {'descr': '<f8', 'fortran_order': False, 'shape': (...), } padded with
// spaces and ended by '\n' so that the data starts at a multiple of 64 bytes, then the raw values
// in C order. We write float64 ('<f8'): positions are integrated in double precision and
// float32 would throw away the digits the RKF45 error control works with. Index tables (a run's
// connectors.npy) are int32 ('<i4'), which NumPy indexes with directly.
//
// NpyWriter streams frames of shape [items, components] into an array of shape
// [frames, items, components] whose frame count is known only at the end (a run can stop early on
// a diagnosis or a signal). The header is written first with room reserved for any 64-bit frame
// count, so close() can rewrite it in place with the true count without moving the data.
// Rejected alternatives: buffering the whole run in memory (trajectories of large sheets do not
// fit), a side-car file with the count (numpy.load could not open the result on its own), and
// NumPy's .npz (a zip container: needs a zip writer and still wants the size up front).
//
// Until close() (or flush()) the header names the frame count of the last rewrite, and readers,
// numpy.load included, read that many frames and ignore the rest: a crashed run leaves a valid
// file holding the frames up to the last flush.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "core/vec3.h"

namespace clothsim {

class NpyWriter {
 public:
  // Creates (truncates) `path` and writes a header for shape [0, items, components].
  // Throws std::runtime_error naming the path and the system's reason if it cannot be created.
  NpyWriter(std::string path, std::size_t items, std::size_t components = 3);
  // Reopens `path`, a file an NpyWriter of the same shape wrote, to go on after its first `frames`
  // frames; anything after them (frames of a run that went on past a checkpoint) is cut off.
  // Throws std::runtime_error naming the path if the file holds fewer data bytes.
  NpyWriter(std::string path, std::size_t items, std::size_t components, std::size_t frames);
  // Closes the file if close() was not called; never throws (errors are lost: call close() to
  // see them).
  ~NpyWriter();

  NpyWriter(const NpyWriter&) = delete;
  NpyWriter& operator=(const NpyWriter&) = delete;
  NpyWriter(NpyWriter&& other) noexcept;
  // Closes this writer's file first, as the destructor would (errors are lost).
  NpyWriter& operator=(NpyWriter&& other) noexcept;

  // Appends one frame of `items` points; requires components == 3. Positions in m (or whatever
  // the caller stores), written as is.
  void append(std::span<const Vec3> frame);
  // Appends one frame of items * components values in C order (item-major).
  void append(std::span<const double> frame);
  // Rewrites the header with the current frame count and flushes the stdio buffer, so that the
  // file on disk is a complete array of the frames so far. Costs a seek and a header write.
  void flush();
  // Rewrites the header with the final frame count and closes the file. Idempotent: later
  // calls do nothing. Throws std::runtime_error on a write or close failure (the file is closed
  // anyway). append() after close() throws.
  void close();

  std::size_t frames() const { return frames_; }
  std::size_t items() const { return items_; }
  std::size_t components() const { return components_; }
  const std::string& path() const { return path_; }
  bool is_open() const { return file_ != nullptr; }

 private:
  // Throws unless the writer is open, healthy and `size` equals `expected` (in `unit`s).
  void check_frame(std::size_t size, const char* unit, std::size_t expected) const;
  // Writes `count` doubles as one frame.
  void write_values(const void* values, std::size_t count);
  void write_header();

  std::string path_;
  std::FILE* file_ = nullptr;
  std::size_t items_ = 0;
  std::size_t components_ = 0;
  std::size_t frames_ = 0;
  std::size_t header_bytes_ = 0;  // preamble + dict + padding, bytes; fixed for the file's life
  bool failed_ = false;           // a frame write failed part-way: refuse further frames
};

// Writes a whole float64 array of the given shape (C order) at once. data.size() must equal the
// product of `shape` (1 for an empty shape, a 0-d array). Throws std::runtime_error naming the
// path on a size mismatch or an I/O failure.
void write_npy(const std::string& path, std::span<const double> data, std::span<const std::size_t> shape);

// Writes a whole int32 ('<i4') array the same way: indices (connectors.npy of a run).
void write_npy(const std::string& path, std::span<const std::int32_t> data, std::span<const std::size_t> shape);

// A float64 array read from a .npy file. data holds the values in C order, product(shape) of them.
struct NpyArray {
  std::vector<std::size_t> shape;
  std::vector<double> data;
};

// Reads a version 1.0 or 2.0 file holding little-endian float64 ('<f8'), or int32 ('<i4',
// converted to double, which is exact), in C order. Anything
// else (other dtype, Fortran order, other versions, a malformed header, too few data bytes)
// throws std::runtime_error naming the path and what is wrong. Bytes past the array's end are
// ignored, as numpy.load does.
NpyArray read_npy(const std::string& path);

// Reads frame `frame` of a float64 file of shape [frames, out.size(), 3] into `out` (the frames
// present in the data count, whatever the header's count says: a crashed run's file). Throws
// std::runtime_error naming the path for another shape or a frame past the end.
void read_npy_frame(const std::string& path, std::size_t frame, std::span<Vec3> out);

}  // namespace clothsim
