// Real-precision helpers the element formulas need and GLSL does not have: norm, and atan2 in
// double precision (GLSL's atan is defined for float only, and Vulkan allows it 4096 ulp).
//
// atan2 is the shared arctangent of forces/arctangent.inc, the lattice kernel's on the CPU, in
// Real precision: float shaders run the same rational function, so their accuracy does not
// depend on the driver's atan either. The element formulas ask only for angles between two
// vectors, atan2(y >= 0, x), which is the range arctangent_upper_half covers. The CPU's general
// element path calls std::atan2 (glibc) instead, which differs from it by about an ulp
// (forces/element.h says why).
#ifndef CLOTHSIM_REAL_MATH_GLSL
#define CLOTHSIM_REAL_MATH_GLSL

#include "gpu/shaders/shared_text.glsl"

Real norm(Vec3 v) { return sqrt(dot(v, v)); }

#include "forces/arctangent.inc"

// atan2(y, x) in [0, pi] for y >= 0, the only angles the element formulas take.
Real atan2(Real y, Real x) { return arctangent_upper_half(y, x); }

#endif
