// The precision of a backend's arithmetic: the values of --precision and the scene's `precision`.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace clothsim {

enum class Precision : std::uint8_t { float64, float32 };

constexpr const char* to_string(Precision precision) { return precision == Precision::float64 ? "float64" : "float32"; }

// "float64" or "float32"; false for any other text (`precision` is then unchanged).
constexpr bool parse_precision(std::string_view text, Precision& precision) {
  if (text == "float64") {
    precision = Precision::float64;
    return true;
  }
  if (text == "float32") {
    precision = Precision::float32;
    return true;
  }
  return false;
}

// Bytes of one real number.
constexpr std::size_t real_size(Precision precision) { return precision == Precision::float64 ? 8 : 4; }

}  // namespace clothsim
