// What the state-checks passes share (state_checks.comp on the lattice path,
// state_checks_elements.comp on the general one; gpu/state_checks.h), included first: the state
// as they read it, a particle's and a spring's terms, and the workgroup's sums written out.
//
// Their arithmetic is double in both variants: the float32 state is read as its two floats a
// coordinate (split_state.glsl) and added in double, so that the sums over a million particles
// keep the host's accuracy (a float sum of the gravitational energies, each a few hundred J,
// would lose whole joules). So the passes need shaderFloat64 in either precision. The arrays stay
// in the variant's precision, `Stored`; Real is double from here on.
#ifndef CLOTHSIM_STATE_CHECKS_GLSL
#define CLOTHSIM_STATE_CHECKS_GLSL

#if CLOTHSIM_FLOAT64
#define Stored double
const bool kSplit = false;
#else
#define Stored float
const bool kSplit = true;  // the state as high + low parts
#endif
#undef CLOTHSIM_FLOAT64
#define CLOTHSIM_FLOAT64 1
#include "gpu/shaders/element_math.glsl"
#include "gpu/shaders/state_checks.h"

const uint kWorkgroupSize = kStateChecksWorkgroup;
layout(local_size_x = kWorkgroupSize) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Position { Stored position[]; };  // [3 particles], m
layout(std430, binding = 1) readonly buffer Velocity { Stored velocity[]; };  // m/s
layout(std430, binding = 2) readonly buffer PositionLow { Stored position_low[]; };  // float32's low parts
layout(std430, binding = 3) readonly buffer VelocityLow { Stored velocity_low[]; };
layout(std430, binding = 4) readonly buffer Mass { Stored particle_mass[]; };  // kg
layout(std430, binding = 5) writeonly buffer BlockChecks { double block_checks[]; };  // [blocks][kStateCheckReals]

Vec3 state_position(uint q) {
  Vec3 x = Vec3(position[3 * q], position[3 * q + 1], position[3 * q + 2]);
  if (kSplit) x += Vec3(position_low[3 * q], position_low[3 * q + 1], position_low[3 * q + 2]);
  return x;
}
Vec3 state_velocity(uint q) {
  Vec3 v = Vec3(velocity[3 * q], velocity[3 * q + 1], velocity[3 * q + 2]);
  if (kSplit) v += Vec3(velocity_low[3 * q], velocity_low[3 * q + 1], velocity_low[3 * q + 2]);
  return v;
}
bool finite(Vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

// A workgroup item's terms, in block_checks' order (kCheckKinetic, ...), none yet.
Real[kStateCheckReals] no_terms() {
  return Real[kStateCheckReals](Real(0.0), Real(0.0), Real(0.0), Real(0.0), Real(0.0), Real(0.0));
}

// Particle p's terms: its kinetic and gravitational energy, J, and a failure where its state is
// not finite.
Real[kStateCheckReals] particle_terms(uint p, Vec3 gravity) {
  const Vec3 x = state_position(p);
  const Vec3 v = state_velocity(p);
  const Real mass = Real(particle_mass[p]);
  Real terms[kStateCheckReals] = no_terms();
  terms[kCheckKinetic] = Real(0.5) * mass * dot(v, v);
  terms[kCheckGravitational] = -mass * dot(gravity, x);
  terms[kCheckFailures] = finite(x) && finite(v) ? Real(0.0) : Real(1.0);
  return terms;
}

// A live connector between xa and xb: its elastic energy, and a failure where it is longer than
// explosion_stretch times its rest length.
void add_connector_terms(inout Real terms[kStateCheckReals], Vec3 xa, Vec3 xb, Real rest_length, Real stiffness,
                         Real explosion_stretch) {
  terms[kCheckConnector] += connector_energy(xa, xb, rest_length, stiffness);
  if (norm(xb - xa) / rest_length > explosion_stretch) terms[kCheckFailures] = Real(1.0);
}

// The rest angle a radial spring's forces act with, for an angle `angle`: in float32 the forces'
// obtuse branch (past pi/2) takes pi - rest_angle in float (element_math.inc,
// add_radial_elastic_force), so that a rest angle of pi rounded to float, the paper's opposite
// springs', acts as pi itself, where the acute branch takes the rounded angle. The energy of the
// device's own dynamics takes it the same way: with the rounded angle alone, the balance of
// float32 runs closed 30 times less well than with the host's sums.
Real acting_rest_angle(Real angle, Stored rest_angle) {
  if (!kSplit || angle <= Real(0.5) * kStraightAngle) return Real(rest_angle);
  const Stored from_straight = Stored(kStraightAngle) - rest_angle;  // in float, as the forces take it
  return kStraightAngle - Real(from_straight);
}

// A radial spring's elastic energy as radial_energy (element_math.inc), with its acting rest angle.
Real checked_radial_energy(Vec3 xa, Vec3 xb, Vec3 xc, Stored rest_angle, Real stiffness, Real fade_length_b,
                           Real fade_length_c) {
  const Real angle = radial_angle(xa, xb, xc);
  const Real d = angle - acting_rest_angle(angle, rest_angle);
  const Real fade = arm_fade(norm(xb - xa), fade_length_b).value * arm_fade(norm(xc - xa), fade_length_c).value;
  return fade * (Real(0.5) * stiffness * d * d);
}

#include "gpu/shaders/workgroup_sums.glsl"

// Every invocation of the workgroup calls it with its terms (kCheckKinetic, ...): their sums over
// the workgroup go to block_checks' row `block`.
void store_workgroup_sums(Real terms[kStateCheckReals], uint block) {
  for (uint first = 0u; first < kStateCheckReals; first += 3u) {
    Real three[3] = Real[3](terms[first], terms[first + 1u], terms[first + 2u]);
    sum_over_workgroup(three);
    if (gl_LocalInvocationID.x == 0u) {
      for (uint k = 0u; k < 3u; ++k) block_checks[kStateCheckReals * block + first + k] = workgroup_sum[k][0];
    }
  }
}

#endif
