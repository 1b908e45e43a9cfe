// The directions of a particle that implicit Euler's solve holds fixed on an obstacle's surface
// (integrators/implicit_euler.h, "Particles resting on an obstacle"): none, its contact normal n
// (sliding), or all three (stuck). The solve then works with the filter S = I - n n^T, or S = 0,
// on that particle: the system S A S, its vectors S v. One definition for the integrator and its
// multigrid preconditioner (integrators/multigrid.h).
#pragma once

#include <cstdint>

#include "core/mat3.h"

namespace clothsim {

enum class Hold : std::uint8_t { none, normal, all };

// S v: v with the held directions removed (the normal is a unit vector where held along it).
inline Vec3 held_vector(Hold hold, const Vec3& normal, const Vec3& v) {
  switch (hold) {
    case Hold::none: return v;
    case Hold::normal: return v - dot(v, normal) * normal;
    case Hold::all: return Vec3{};
  }
  return v;
}

// S_p B S_q with S = I - n n^T (the identity where n is zero): the block of the held system,
// B - n_p (B^T n_p)^T - (B n_q) n_q^T + (n_p . B n_q) n_p n_q^T. (Particles held in all
// directions have S = 0: their blocks are zero, which the callers handle.)
inline Mat3 held_block(const Mat3& b, const Vec3& np, const Vec3& nq) {
  const Vec3 bt_np = transpose_times(b, np);
  const Vec3 b_nq = b * nq;
  return b - outer(np, bt_np) - outer(b_nq, nq) + dot(np, b_nq) * outer(np, nq);
}

// S_p B S_q for the holds of p and q.
inline Mat3 held_block(const Mat3& b, Hold hold_p, const Vec3& np, Hold hold_q, const Vec3& nq) {
  if (hold_p == Hold::all || hold_q == Hold::all) return Mat3{};
  return held_block(b, np, nq);
}

}  // namespace clothsim
