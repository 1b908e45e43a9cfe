// The CPU's arrays in the device's layout: Reals in the chosen precision (doubles as they are,
// so float64 uploads the CPU's structure-of-arrays unchanged; floats rounded one by one), Vec3
// arrays as 3 Reals each, index arrays as 32-bit words. And back to doubles.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "core/vec3.h"
#include "gpu/device.h"

namespace clothsim::gpu {

inline std::vector<std::byte> real_bytes(std::span<const double> values, Precision precision) {
  std::vector<std::byte> bytes(values.size() * real_size(precision));
  if (precision == Precision::float64) {
    if (!values.empty()) std::memcpy(bytes.data(), values.data(), bytes.size());
  } else {
    for (std::size_t i = 0; i < values.size(); ++i) {
      const float value = static_cast<float>(values[i]);
      std::memcpy(bytes.data() + 4 * i, &value, 4);
    }
  }
  return bytes;
}

inline std::vector<std::byte> vector_bytes(std::span<const Vec3> vectors, Precision precision) {
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 is three packed doubles");
  if (vectors.empty()) return {};
  return real_bytes(std::span<const double>(&vectors.data()->x, 3 * vectors.size()), precision);
}

template <typename Index>
std::vector<std::byte> index_bytes(std::span<const Index> indices) {
  std::vector<std::byte> bytes(indices.size_bytes());
  if (!indices.empty()) std::memcpy(bytes.data(), indices.data(), bytes.size());
  return bytes;
}

// The index-th Real of an array in the device's layout (a mapped host-visible buffer, say), in
// place: no copy of the array.
inline double load_real(const std::byte* reals, std::size_t index, Precision precision) {
  if (precision == Precision::float64) {
    double value = 0.0;
    std::memcpy(&value, reals + 8 * index, 8);
    return value;
  }
  float value = 0.0f;
  std::memcpy(&value, reals + 4 * index, 4);
  return static_cast<double>(value);
}

inline void store_real(std::byte* reals, std::size_t index, double value, Precision precision) {
  if (precision == Precision::float64) {
    std::memcpy(reals + 8 * index, &value, 8);
  } else {
    const float single = static_cast<float>(value);
    std::memcpy(reals + 4 * index, &single, 4);
  }
}

inline std::vector<double> reals_from_bytes(std::span<const std::byte> bytes, Precision precision) {
  std::vector<double> values(bytes.size() / real_size(precision));
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (precision == Precision::float64) {
      std::memcpy(&values[i], bytes.data() + 8 * i, 8);
    } else {
      float value = 0.0f;
      std::memcpy(&value, bytes.data() + 4 * i, 4);
      values[i] = value;
    }
  }
  return values;
}

inline std::vector<Vec3> vectors_from_bytes(std::span<const std::byte> bytes, Precision precision) {
  const std::vector<double> reals = reals_from_bytes(bytes, precision);
  std::vector<Vec3> vectors(reals.size() / 3);
  for (std::size_t i = 0; i < vectors.size(); ++i) vectors[i] = {reals[3 * i], reals[3 * i + 1], reals[3 * i + 2]};
  return vectors;
}

// Whether the device keeps the state as two floats a coordinate and the stages as offsets from
// it: float32 (the shaders' CLOTHSIM_STAGE_OFFSETS, shaders/device_step.h; stage_offsets.glsl and
// split_state.glsl say why).
inline bool splits_state(Precision precision) { return precision == Precision::float32; }

// x as the device's float32 state holds it (shaders/split_state.glsl's canonical_split): the
// float nearest x, and the rest on the 2^-48 grid of its binade. For a double that came from the
// device (high + low), the same two floats.
struct SplitFloat {
  float high;
  float low;
};

inline SplitFloat split_real(double x) {
  float high = static_cast<float>(x);
  if (std::abs(high) < 0x1p-60f) return {high, 0.0f};
  int binade = 0;
  std::frexp(high, &binade);
  const double rest = x - static_cast<double>(high);  // exact
  double low = std::ldexp(std::nearbyint(std::ldexp(rest, 48 - binade)), binade - 48);
  const auto nearest = static_cast<float>(static_cast<double>(high) + low);  // the sum is exact
  if (nearest != high) {
    low -= static_cast<double>(nearest) - static_cast<double>(high);
    high = nearest;
  }
  return {high, static_cast<float>(low)};
}

}  // namespace clothsim::gpu
