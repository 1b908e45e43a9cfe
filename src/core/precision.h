// The precision of a backend's arithmetic, and what --precision and the scene's `precision` ask for.
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

// What a scene or a flag asks for: a precision, or `auto`, which the backend resolves from the
// requested accuracy (BackendSettings::resolved_precision, sim/backend.h).
enum class PrecisionRequest : std::uint8_t { float64, float32, automatic };

constexpr PrecisionRequest request(Precision precision) {
  return precision == Precision::float64 ? PrecisionRequest::float64 : PrecisionRequest::float32;
}

constexpr const char* to_string(PrecisionRequest request) {
  return request == PrecisionRequest::float64   ? "float64"
         : request == PrecisionRequest::float32 ? "float32"
                                                : "auto";
}

// "float64", "float32" or "auto"; false for any other text (`request` is then unchanged).
constexpr bool parse_precision_request(std::string_view text, PrecisionRequest& request) {
  Precision precision = Precision::float64;
  if (parse_precision(text, precision)) {
    request = clothsim::request(precision);
    return true;
  }
  if (text == "auto") {
    request = PrecisionRequest::automatic;
    return true;
  }
  return false;
}

// Bytes of one real number.
constexpr std::size_t real_size(Precision precision) { return precision == Precision::float64 ? 8 : 4; }

}  // namespace clothsim
