// 3x3 matrices for the blocks of implicit integration: element Jacobians and the 3x3 blocks of
// the block-sparse system matrix (integrators/implicit_euler.h).
//
// Row-major, three Vec3 rows, double precision like Vec3. Only what the Jacobians and the
// conjugate-gradient solver need: products with vectors, outer products, sums, the identity, the
// transpose, and the inverse of a symmetric positive definite block (the Jacobi preconditioner).
#pragma once

#include <array>

#include "core/vec3.h"

namespace clothsim {

struct Mat3 {
  Vec3 row0, row1, row2;

  static constexpr Mat3 identity() { return {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}; }
  static constexpr Mat3 diagonal(double s) { return {{s, 0, 0}, {0, s, 0}, {0, 0, s}}; }

  constexpr Mat3& operator+=(const Mat3& o) {
    row0 += o.row0;
    row1 += o.row1;
    row2 += o.row2;
    return *this;
  }
  constexpr Mat3& operator-=(const Mat3& o) {
    row0 -= o.row0;
    row1 -= o.row1;
    row2 -= o.row2;
    return *this;
  }
  // Entry (row, col), both in [0, 3).
  constexpr double operator()(int row, int col) const { return (row == 0 ? row0 : (row == 1 ? row1 : row2))[col]; }
};

constexpr Mat3 operator+(const Mat3& a, const Mat3& b) { return {a.row0 + b.row0, a.row1 + b.row1, a.row2 + b.row2}; }
constexpr Mat3 operator-(const Mat3& a, const Mat3& b) { return {a.row0 - b.row0, a.row1 - b.row1, a.row2 - b.row2}; }
constexpr Mat3 operator-(const Mat3& a) { return {-a.row0, -a.row1, -a.row2}; }
constexpr Mat3 operator*(double s, const Mat3& a) { return {s * a.row0, s * a.row1, s * a.row2}; }
constexpr Vec3 operator*(const Mat3& a, const Vec3& v) { return {dot(a.row0, v), dot(a.row1, v), dot(a.row2, v)}; }

// a b^T.
constexpr Mat3 outer(const Vec3& a, const Vec3& b) { return {a.x * b, a.y * b, a.z * b}; }

// a^T.
constexpr Mat3 transpose(const Mat3& a) {
  return {Vec3{a.row0.x, a.row1.x, a.row2.x}, Vec3{a.row0.y, a.row1.y, a.row2.y}, Vec3{a.row0.z, a.row1.z, a.row2.z}};
}
// a^T v.
constexpr Vec3 transpose_times(const Mat3& a, const Vec3& v) { return v.x * a.row0 + v.y * a.row1 + v.z * a.row2; }
// a b^T for matrices.
constexpr Mat3 times_transpose(const Mat3& a, const Mat3& b) {
  return {Vec3{dot(a.row0, b.row0), dot(a.row0, b.row1), dot(a.row0, b.row2)},
          Vec3{dot(a.row1, b.row0), dot(a.row1, b.row1), dot(a.row1, b.row2)},
          Vec3{dot(a.row2, b.row0), dot(a.row2, b.row1), dot(a.row2, b.row2)}};
}

// Inverse by cofactors; the caller guarantees a non-singular matrix (a mass-dominated diagonal
// block of the implicit system is symmetric positive definite).
constexpr Mat3 inverse(const Mat3& a) {
  const Vec3 c0 = cross(a.row1, a.row2);
  const Vec3 c1 = cross(a.row2, a.row0);
  const Vec3 c2 = cross(a.row0, a.row1);
  const double inverse_determinant = 1.0 / dot(a.row0, c0);
  // The inverse's columns are the cofactor vectors divided by the determinant.
  return {inverse_determinant * Vec3{c0.x, c1.x, c2.x}, inverse_determinant * Vec3{c0.y, c1.y, c2.y},
          inverse_determinant * Vec3{c0.z, c1.z, c2.z}};
}

// A 3x3 block stored in single precision, row-major, for the preconditioner's matrices, whose
// rounding (6e-8 relative) only changes how well they precondition: half the bytes to read per
// sweep. Products with it sum in double.
using FloatBlock = std::array<float, 9>;

inline FloatBlock narrow(const Mat3& a) {
  return {static_cast<float>(a.row0.x), static_cast<float>(a.row0.y), static_cast<float>(a.row0.z),
          static_cast<float>(a.row1.x), static_cast<float>(a.row1.y), static_cast<float>(a.row1.z),
          static_cast<float>(a.row2.x), static_cast<float>(a.row2.y), static_cast<float>(a.row2.z)};
}
constexpr Mat3 widen(const FloatBlock& m) {
  return {Vec3{m[0], m[1], m[2]}, Vec3{m[3], m[4], m[5]}, Vec3{m[6], m[7], m[8]}};
}
// m v.
constexpr Vec3 times(const FloatBlock& m, const Vec3& v) {
  return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
          m[6] * v.x + m[7] * v.y + m[8] * v.z};
}
// m^T v.
constexpr Vec3 transpose_times(const FloatBlock& m, const Vec3& v) {
  return {m[0] * v.x + m[3] * v.y + m[6] * v.z, m[1] * v.x + m[4] * v.y + m[7] * v.z,
          m[2] * v.x + m[5] * v.y + m[8] * v.z};
}

}  // namespace clothsim
