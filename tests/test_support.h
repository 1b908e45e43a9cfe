// Small helpers shared by the tests: deterministic random vectors and finite differences.
#pragma once

#include <array>
#include <cctype>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/vec3.h"

namespace clothsim::testing {

// A parameterised case's name for gtest and ctest: `text` with every character that is not a letter
// or a digit as '_' ("paper-fig4" -> "paper_fig4", "rows 2.5" -> "rows_2_5").
inline std::string case_name(std::string text) {
  for (char& c : text) {
    if (std::isalnum(static_cast<unsigned char>(c)) == 0) c = '_';
  }
  return text;
}

// Deterministic uniform numbers for test configurations (SplitMix64).
class TestRandom {
 public:
  explicit TestRandom(std::uint64_t seed) : state_(seed) {}
  double uniform(double lo, double hi) {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return lo + (hi - lo) * static_cast<double>(z >> 11) * 0x1.0p-53;
  }
  Vec3 vector(double lo, double hi) { return {uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)}; }

 private:
  std::uint64_t state_;
};

// Central-difference gradient of a scalar function of one point: (f(x + h e_k) - f(x - h e_k)) / 2h.
inline Vec3 numerical_gradient(const std::function<double(const Vec3&)>& f, const Vec3& x, double h) {
  Vec3 g;
  g.x = (f(x + Vec3{h, 0, 0}) - f(x - Vec3{h, 0, 0})) / (2 * h);
  g.y = (f(x + Vec3{0, h, 0}) - f(x - Vec3{0, h, 0})) / (2 * h);
  g.z = (f(x + Vec3{0, 0, h}) - f(x - Vec3{0, 0, h})) / (2 * h);
  return g;
}

// Normal of a triangle of `position`, of length twice its area, oriented by its winding.
inline Vec3 face_normal(const std::vector<Vec3>& position, const std::array<std::uint32_t, 3>& triangle) {
  return cross(position[triangle[1]] - position[triangle[0]], position[triangle[2]] - position[triangle[0]]);
}

}  // namespace clothsim::testing
