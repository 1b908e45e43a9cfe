// PC2 point caches: the positions of a fixed set of points at every frame, in the format that
// Blender's Mesh Cache modifier, 3ds Max's Point Cache and other tools read.
//
// Format (all little-endian):
//   char[12]  "POINTCACHE2\0"
//   int32     version, 1
//   int32     number of points
//   float32   start frame
//   float32   sample rate: frames between samples
//   int32     number of samples
//   then samples x points x 3 float32: x, y, z of each point, sample after sample.
// The points are the vertices of a mesh file beside the cache (a run's rest.obj), in its order;
// a reader applies sample k to the mesh at frame start + k * rate.
//
// Like NpyWriter, Pc2Writer streams: the header is written first with 0 samples and close()
// rewrites the count in place, so a trajectory never has to fit in memory. Until close() the
// header says 0 samples; a run's output folder is only ever seen after close() (run/run_writer.h).
// Positions are rounded from double to the nearest float32, the only precision the format has.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "core/vec3.h"

namespace clothsim {

class Pc2Writer {
 public:
  static constexpr char kMagic[12] = "POINTCACHE2";  // with its terminating '\0', 12 bytes
  static constexpr std::int32_t kVersion = 1;
  static constexpr std::size_t kHeaderBytes = 32;

  // Creates (truncates) `path` and writes the header for `point_count` points and 0 samples.
  // Throws std::runtime_error naming the path and the reason (also when point_count does not
  // fit the format's int32).
  Pc2Writer(std::string path, std::size_t point_count, float start_frame, float sample_rate);
  // Reopens `path`, a cache of `point_count` points a Pc2Writer wrote, to go on after its first
  // `samples` samples; later ones are cut off. Throws std::runtime_error naming the path if the
  // file is not such a cache or holds fewer samples.
  Pc2Writer(std::string path, std::size_t point_count, std::size_t samples);
  // Closes the file if close() was not called; never throws (call close() to see errors).
  ~Pc2Writer();

  Pc2Writer(const Pc2Writer&) = delete;
  Pc2Writer& operator=(const Pc2Writer&) = delete;

  // Appends one sample: `position` [point_count], m, rounded to float32. Throws on a size
  // mismatch or a write error.
  void append(std::span<const Vec3> position);
  // Hands the buffered samples to the operating system. Throws on failure.
  void flush();
  // Writes the sample count into the header and closes the file. Throws on failure.
  void close();

  std::size_t samples() const { return samples_; }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  std::size_t point_count_ = 0;
  std::size_t samples_ = 0;
  std::vector<float> buffer_;  // [point_count * 3], one sample, reused
};

}  // namespace clothsim
