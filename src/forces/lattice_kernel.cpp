// The structured force kernel for a lattice, intact or torn; the design is in lattice_kernel.h.
#include "forces/lattice_kernel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "core/assert.h"
#include "core/multiversion.h"
#include "forces/element.h"
#include "forces/forces.h"
#include "forces/lattice_kernel_layout.h"
#include "forces/vector_math.h"

namespace clothsim {
namespace {

using namespace lattice_layout;

// Particles per band of the radial and gather passes (at least; bands are whole rows).
constexpr std::size_t kBandParticles = 256;

// The row and band functions are compiled for AVX-512, AVX2 and baseline x86-64 and chosen at
// load time (core/multiversion.h).

// Switches of one evaluation: 1 for a force term that is on, 0 for one that is off, multiplied
// onto the per-spring constants (multiplying by 1 is exact, so a term that is on gives the same
// bits as without the switch). On a uniform sheet, also the one value of each parameter of each
// family, read instead of the parameter arrays: the products are the same as with the arrays,
// so both forms give the same bits.
struct Coefficients {
  double connector_elastic = 0.0;
  double connector_damped = 0.0;
  double adjacent_elastic = 0.0;
  double adjacent_damped = 0.0;
  double opposite_elastic = 0.0;
  double opposite_damped = 0.0;
  Vec3 gravity;
  double drag = 0.0;
  // Uniform sheets only.
  double connector_stiffness = 0.0;
  double connector_damping = 0.0;
  double connector_rest_length = 0.0;
  double adjacent_stiffness = 0.0;
  double adjacent_damping = 0.0;
  double adjacent_rest_angle = 0.0;
  double opposite_stiffness = 0.0;
  double opposite_damping = 0.0;
  double opposite_rest_angle = 0.0;
};

// One radial spring between the connectors centre->b and centre->c, from their unit vectors and
// inverse lengths (0: no such connector) and the relative velocities v_b - v_a, v_c - v_a. The
// formulas are those of element::radial_force, rearranged to multiply by 1/length and
// 1/sin(theta) once and to scale w = sin(theta) p instead of forming p. A singular spring
// (sin(theta) < kSingularSine) gets meaningless values from the kResolveSingular = false version,
// which only reports it through `singular`; the caller then recomputes it with the true version,
// which takes the bending plane from the motion like element::resolve_singular_directions.
struct RadialResult {
  Vec3 on_b;
  Vec3 on_c;
  double power = 0.0;
  double singular = 0.0;  // > 0 if the spring is singular (a double: GCC vectorises it better than a bool)
};

template <bool kResolveSingular>
[[gnu::always_inline]] inline RadialResult radial_spring(const Vec3& ub, double inverse_b, const Vec3& uc,
                                                         double inverse_c, const Vec3& rb, const Vec3& rc,
                                                         double stiffness, double damping, double rest_angle) {
  const bool exists = std::min(inverse_b, inverse_c) > 0.0;
  const Vec3 n = cross(ub, uc);
  const double cosine = dot(ub, uc);
  const double sine = std::sqrt(dot(n, n));
  const Vec3 wb = cross(n, ub);  // sin(theta) p_b
  const Vec3 wc = cross(uc, n);  // sin(theta) p_c
  const double inverse_sine = 1.0 / sine;
  const bool obtuse = cosine < 0.0;
  RadialResult out;
  out.singular = exists ? element::kSingularSine - sine : -1.0;
  // theta (acute) or pi - theta (obtuse), and (that angle) / sin(theta) without cancellation.
  const double angle = vector_math::atan2_first_quadrant(sine, std::abs(cosine));
  const double angle2 = angle * angle;
  const double series = 1.0 + angle2 * (1.0 / 6.0 + angle2 * (7.0 / 360.0));
  const double ratio = angle < 1e-4 ? series : angle * inverse_sine;
  const double smooth = obtuse ? -ratio : ratio;
  const double constant = obtuse ? std::numbers::pi - rest_angle : -rest_angle;
  const double kb = stiffness * inverse_b;
  const double kc = stiffness * inverse_c;
  // p = w / sin(theta) is parallel to w, so every force along p is a multiple of w:
  //   f_b = [k/l_b (A + B / sin) + torque (-1/(l_b sin))] w_b,  dtheta/dx_b = -w_b / (l_b sin).
  const double gradient_b = -inverse_b * inverse_sine;
  const double gradient_c = -inverse_c * inverse_sine;
  double angle_rate = gradient_b * dot(wb, rb) + gradient_c * dot(wc, rc);
  double torque = -damping * angle_rate;
  const double elastic = smooth + constant * inverse_sine;
  Vec3 fb = (kb * elastic + torque * gradient_b) * wb;
  Vec3 fc = (kc * elastic + torque * gradient_c) * wc;
  if constexpr (kResolveSingular) {
    // Singular: the bending plane from the motion (element::resolve_singular_directions).
    // Computed for every spring and selected, so that this loop vectorises too; non-singular
    // springs keep exactly the values above.
    const Vec3 turn_b = inverse_b * (rb - dot(rb, ub) * ub);
    const Vec3 turn_c = inverse_c * (rc - dot(rc, uc) * uc);
    const Vec3 opening = obtuse ? turn_b + turn_c : turn_c - turn_b;
    const double rate = std::sqrt(dot(opening, opening));
    // Rounding-sized openings have no direction (element::resolve_singular_directions).
    const double turning = inverse_b * std::sqrt(dot(rb, rb)) + inverse_c * std::sqrt(dot(rc, rc));
    const double inverse_rate = rate > element::kSingularSine * turning ? 1.0 / rate : 0.0;
    const Vec3 pb = inverse_rate * opening;
    const Vec3 pc = obtuse ? pb : -pb;
    Vec3 singular_fb = kb * (smooth * wb + constant * pb);
    Vec3 singular_fc = kc * (smooth * wc + constant * pc);
    const Vec3 gb = -inverse_b * pb;  // dtheta/dx_b
    const Vec3 gc = -inverse_c * pc;
    const double singular_rate = dot(gb, rb) + dot(gc, rc);
    const double singular_torque = -damping * singular_rate;
    singular_fb += singular_torque * gb;
    singular_fc += singular_torque * gc;
    const bool use = out.singular > 0.0;
    fb = {use ? singular_fb.x : fb.x, use ? singular_fb.y : fb.y, use ? singular_fb.z : fb.z};
    fc = {use ? singular_fc.x : fc.x, use ? singular_fc.y : fc.y, use ? singular_fc.z : fc.z};
    angle_rate = use ? singular_rate : angle_rate;
    torque = use ? singular_torque : torque;
  }
  out.on_b = {exists ? fb.x : 0.0, exists ? fb.y : 0.0, exists ? fb.z : 0.0};
  out.on_c = {exists ? fc.x : 0.0, exists ? fc.y : 0.0, exists ? fc.z : 0.0};
  out.power = exists ? torque * angle_rate : 0.0;
  return out;
}

// Pointers into the scratch, offset past the padding: index p is particle p, p - 1 its west
// neighbour, p - cols its north neighbour (or padding / the previous row's last particle, whose
// east connector does not exist: either way a zero connector).
struct Arrays {
  double* a[kArrayCount];
  double* operator[](std::size_t k) const { return a[k]; }
};

// Connector from each particle p in [begin, missing_from) to p + offset (east: 1, south: cols),
// read straight from the Vec3 arrays; particles from `missing_from` to `end` have none (the last
// column has no east connector, the last row no south one). kUniform: the parameters are the
// family's (Coefficients), every connector intact.
template <bool kUniform>
[[gnu::always_inline]] inline void connector_row_of(const Arrays& s, const Coefficients& k, const Vec3* __restrict x,
                                                    const Vec3* __restrict v, std::size_t begin, std::size_t end,
                                                    std::size_t offset, std::size_t missing_from, std::size_t ux_array,
                                                    double* __restrict power) {
  double* __restrict ux = s[ux_array];
  double* __restrict uy = s[ux_array + 1];
  double* __restrict uz = s[ux_array + 2];
  double* __restrict inverse_length = s[ux_array + 3];
  double* __restrict tension = s[ux_array + 4];
  // The parameter arrays of this direction (east and south are laid out alike); null when uniform.
  const std::size_t parameters = ux_array == kEastX ? kEastStiffness : kSouthStiffness;
  const double* __restrict stiffness = kUniform ? nullptr : s[parameters];
  const double* __restrict damping = kUniform ? nullptr : s[parameters + 1];
  const double* __restrict rest_length = kUniform ? nullptr : s[parameters + 2];
  const double* __restrict live = kUniform ? nullptr : s[parameters + 3];
  const double elastic = k.connector_elastic;
  const double damped = k.connector_damped;
#pragma GCC ivdep
  for (std::size_t p = begin; p < missing_from; ++p) {
    const Vec3 e = x[p + offset] - x[p];
    const double length = std::sqrt(dot(e, e));
    // A broken connector is stored like a missing one: 1/length = 0 and no tension, which also
    // switches off the radial springs that use it.
    const bool exists = length > 0.0 && (kUniform || live[p] > 0.0);
    const double inverse = exists ? 1.0 / length : 0.0;
    const Vec3 u = inverse * e;
    const double rate = dot(v[p + offset] - v[p], u);
    const double c = damped * (kUniform ? k.connector_damping : damping[p]);
    const double t = elastic * (kUniform ? k.connector_stiffness : stiffness[p]) *
                         (length - (kUniform ? k.connector_rest_length : rest_length[p])) +
                     c * rate;
    ux[p] = u.x;
    uy[p] = u.y;
    uz[p] = u.z;
    inverse_length[p] = inverse;
    tension[p] = exists ? t : 0.0;
    power[p] += exists ? -c * rate * rate : 0.0;
  }
  // No connector from the last column eastwards, or from the last row southwards.
  for (std::size_t p = missing_from; p < end; ++p) ux[p] = uy[p] = uz[p] = inverse_length[p] = tension[p] = 0.0;
}

CLOTHSIM_MULTIVERSION void connector_row(const Arrays& s, const Coefficients& k, const Vec3* __restrict x,
                                         const Vec3* __restrict v, std::size_t begin, std::size_t end,
                                         std::size_t offset, std::size_t missing_from, std::size_t ux_array,
                                         double* __restrict power) {
  connector_row_of<false>(s, k, x, v, begin, end, offset, missing_from, ux_array, power);
}

CLOTHSIM_MULTIVERSION void uniform_connector_row(const Arrays& s, const Coefficients& k, const Vec3* __restrict x,
                                                 const Vec3* __restrict v, std::size_t begin, std::size_t end,
                                                 std::size_t offset, std::size_t missing_from, std::size_t ux_array,
                                                 double* __restrict power) {
  connector_row_of<true>(s, k, x, v, begin, end, offset, missing_from, ux_array, power);
}

// The row's velocities into the SoA arrays read by the radial and gather passes.
CLOTHSIM_MULTIVERSION void velocity_row(const Arrays& s, const Vec3* __restrict v, std::size_t begin, std::size_t end) {
  double* __restrict vx = s[kVelocityX];
  double* __restrict vy = s[kVelocityY];
  double* __restrict vz = s[kVelocityZ];
#pragma GCC ivdep
  for (std::size_t p = begin; p < end; ++p) {
    vx[p] = v[p].x;
    vy[p] = v[p].y;
    vz[p] = v[p].z;
  }
}

// A connector of particle p seen from p: unit vector towards the neighbour, 1/length, and the
// neighbour's velocity relative to p's. Directions: 0 east, 1 south, 2 west, 3 north.
struct Arm {
  Vec3 unit;
  double inverse_length = 0.0;
  Vec3 relative_velocity;
};

template <int kDirection>
[[gnu::always_inline]] inline Arm arm(const Arrays& s, std::size_t p, std::size_t cols) {
  const std::size_t q = kDirection == 0 ? p + 1 : kDirection == 1 ? p + cols : kDirection == 2 ? p - 1 : p - cols;
  Arm out;
  if constexpr (kDirection == 0) {
    out.unit = {s[kEastX][p], s[kEastY][p], s[kEastZ][p]};
    out.inverse_length = s[kEastInverseLength][p];
  } else if constexpr (kDirection == 1) {
    out.unit = {s[kSouthX][p], s[kSouthY][p], s[kSouthZ][p]};
    out.inverse_length = s[kSouthInverseLength][p];
  } else if constexpr (kDirection == 2) {
    out.unit = {-s[kEastX][q], -s[kEastY][q], -s[kEastZ][q]};
    out.inverse_length = s[kEastInverseLength][q];
  } else {
    out.unit = {-s[kSouthX][q], -s[kSouthY][q], -s[kSouthZ][q]};
    out.inverse_length = s[kSouthInverseLength][q];
  }
  out.relative_velocity = {s[kVelocityX][q] - s[kVelocityX][p], s[kVelocityY][q] - s[kVelocityY][p],
                           s[kVelocityZ][q] - s[kVelocityZ][p]};
  return out;
}

// Index of the pair (kB, kC) in kPairs.
template <int kB, int kC>
constexpr std::size_t pair_index() {
  for (std::size_t i = 0; i < kPairs.size(); ++i) {
    if (kPairs[i][0] == kB && kPairs[i][1] == kC) return i;
  }
  return kPairs.size();
}

// The spring between arms kB and kC of particle p, with its own stiffness, damping and rest angle
// (kUniform: its family's). On a uniform sheet a spring that does not exist (at a border) has the
// family's values, not zeros, and contributes nothing all the same: one of its arms has 1/length 0.
template <bool kUniform, bool kResolveSingular, int kB, int kC>
[[gnu::always_inline]] inline RadialResult spring_at(const Arrays& s, const Coefficients& k, std::size_t p,
                                                     std::size_t cols) {
  constexpr bool kOpposite = (kB + 2) % 4 == kC;
  constexpr std::size_t kPair = pair_index<kB, kC>();
  static_assert(kPair < kPairs.size());
  const Arm b = arm<kB>(s, p, cols);
  const Arm c = arm<kC>(s, p, cols);
  const double elastic = kOpposite ? k.opposite_elastic : k.adjacent_elastic;
  const double damped = kOpposite ? k.opposite_damped : k.adjacent_damped;
  double stiffness = 0.0;
  double damping = 0.0;
  double rest_angle = 0.0;
  if constexpr (kUniform) {
    stiffness = kOpposite ? k.opposite_stiffness : k.adjacent_stiffness;
    damping = kOpposite ? k.opposite_damping : k.adjacent_damping;
    rest_angle = kOpposite ? k.opposite_rest_angle : k.adjacent_rest_angle;
  } else {
    stiffness = s[kRadialStiffness + kPair][p];
    damping = s[kRadialDamping + kPair][p];
    rest_angle = s[kRadialRestAngle + kPair][p];
  }
  return radial_spring<kResolveSingular>(b.unit, b.inverse_length, c.unit, c.inverse_length, b.relative_velocity,
                                         c.relative_velocity, elastic * stiffness, damped * damping, rest_angle);
}

// The to_<direction> x array of each direction.
constexpr std::array<std::size_t, 4> kToArray = {kToEastX, kToSouthX, kToWestX, kToNorthX};

// The six radial springs centred at particle p, in the order (E,S), (S,W), (W,N), (N,E), (E,W),
// (S,N), written as forces on its four neighbours; each neighbour's sum and the power are
// accumulated in that order (resolve_spring_row repeats exactly these sums). Returns a positive
// number if one of the springs is singular.
template <bool kUniform>
[[gnu::always_inline]] inline double radial_particle(const Arrays& s, const Coefficients& k, std::size_t p,
                                                     std::size_t cols) {
  const RadialResult es = spring_at<kUniform, false, 0, 1>(s, k, p, cols);
  const RadialResult sw = spring_at<kUniform, false, 1, 2>(s, k, p, cols);
  const RadialResult wn = spring_at<kUniform, false, 2, 3>(s, k, p, cols);
  const RadialResult ne = spring_at<kUniform, false, 3, 0>(s, k, p, cols);
  const RadialResult ew = spring_at<kUniform, false, 0, 2>(s, k, p, cols);
  const RadialResult sn = spring_at<kUniform, false, 1, 3>(s, k, p, cols);
  const Vec3 to_east = es.on_b + ne.on_c + ew.on_b;
  const Vec3 to_south = es.on_c + sw.on_b + sn.on_b;
  const Vec3 to_west = sw.on_c + wn.on_b + ew.on_c;
  const Vec3 to_north = wn.on_c + ne.on_b + sn.on_c;
  s[kToEastX][p] = to_east.x;
  s[kToEastY][p] = to_east.y;
  s[kToEastZ][p] = to_east.z;
  s[kToSouthX][p] = to_south.x;
  s[kToSouthY][p] = to_south.y;
  s[kToSouthZ][p] = to_south.z;
  s[kToWestX][p] = to_west.x;
  s[kToWestY][p] = to_west.y;
  s[kToWestZ][p] = to_west.z;
  s[kToNorthX][p] = to_north.x;
  s[kToNorthY][p] = to_north.y;
  s[kToNorthZ][p] = to_north.z;
  s[kPower][p] = s[kConnectorPower][p] + es.power + sw.power + wn.power + ne.power + ew.power + sn.power;
  return std::max(std::max(std::max(es.singular, sw.singular), std::max(wn.singular, ne.singular)),
                  std::max(ew.singular, sn.singular));
}

// Recomputes one of the six springs for a band with singular springs resolved, adding its forces
// into the neighbours' sums in the order of radial_particle (`first_b`/`first_c`: the spring is
// the first term of that neighbour's sum). One spring per loop keeps the body small enough for
// GCC to if-convert and vectorise it; inlined, so it is compiled into each clone of radial_band.
template <bool kUniform, int kB, int kC, bool kFirstB, bool kFirstC>
[[gnu::always_inline]] inline void resolve_spring_row(const Arrays& s, const Coefficients& k, std::size_t begin,
                                                      std::size_t end, std::size_t cols) {
  double* __restrict bx = s[kToArray[kB]];
  double* __restrict by = s[kToArray[kB] + 1];
  double* __restrict bz = s[kToArray[kB] + 2];
  double* __restrict cx = s[kToArray[kC]];
  double* __restrict cy = s[kToArray[kC] + 1];
  double* __restrict cz = s[kToArray[kC] + 2];
  double* __restrict power = s[kPower];
#pragma GCC ivdep
  for (std::size_t p = begin; p < end; ++p) {
    const RadialResult r = spring_at<kUniform, true, kB, kC>(s, k, p, cols);
    bx[p] = (kFirstB ? 0.0 : bx[p]) + r.on_b.x;
    by[p] = (kFirstB ? 0.0 : by[p]) + r.on_b.y;
    bz[p] = (kFirstB ? 0.0 : bz[p]) + r.on_b.z;
    cx[p] = (kFirstC ? 0.0 : cx[p]) + r.on_c.x;
    cy[p] = (kFirstC ? 0.0 : cy[p]) + r.on_c.y;
    cz[p] = (kFirstC ? 0.0 : cz[p]) + r.on_c.z;
    power[p] += r.power;
  }
}

template <bool kUniform>
[[gnu::always_inline]] inline void radial_band_of(const Arrays& arrays, const Coefficients& coefficients,
                                                  std::size_t begin, std::size_t end, std::size_t cols) {
  // Local copies, so that the compiler sees the array pointers and coefficients as loop invariant.
  const Arrays s = arrays;
  const Coefficients k = coefficients;
  double* __restrict singular = s[kSingular];
  int any_singular = 0;
#pragma GCC ivdep
  for (std::size_t p = begin; p < end; ++p) {
    singular[p] = radial_particle<kUniform>(s, k, p, cols);
    any_singular |= singular[p] > 0.0 ? 1 : 0;
  }
  if (any_singular != 0) {
    // A straight or folded spring in this band (a flat sheet, at the start of most runs; a
    // symmetry line): redo the band spring by spring with the bending plane taken from the motion
    // where it is undefined. Particles without a singular spring get the same values again.
    double* __restrict power = s[kPower];
    for (std::size_t p = begin; p < end; ++p) power[p] = s[kConnectorPower][p];
    resolve_spring_row<kUniform, 0, 1, true, true>(s, k, begin, end, cols);    // (E,S): first into east and south
    resolve_spring_row<kUniform, 1, 2, false, true>(s, k, begin, end, cols);   // (S,W): first into west
    resolve_spring_row<kUniform, 2, 3, false, true>(s, k, begin, end, cols);   // (W,N): first into north
    resolve_spring_row<kUniform, 3, 0, false, false>(s, k, begin, end, cols);  // (N,E)
    resolve_spring_row<kUniform, 0, 2, false, false>(s, k, begin, end, cols);  // (E,W)
    resolve_spring_row<kUniform, 1, 3, false, false>(s, k, begin, end, cols);  // (S,N)
  }
}

CLOTHSIM_MULTIVERSION void radial_band(const Arrays& arrays, const Coefficients& coefficients, std::size_t begin,
                                       std::size_t end, std::size_t cols) {
  radial_band_of<false>(arrays, coefficients, begin, end, cols);
}

CLOTHSIM_MULTIVERSION void uniform_radial_band(const Arrays& arrays, const Coefficients& coefficients,
                                               std::size_t begin, std::size_t end, std::size_t cols) {
  radial_band_of<true>(arrays, coefficients, begin, end, cols);
}

CLOTHSIM_MULTIVERSION void gather_band(const Arrays& arrays, const Coefficients& coefficients,
                                       const double* __restrict mass, std::size_t begin, std::size_t end,
                                       std::size_t cols, Vec3* __restrict force) {
  const Arrays s = arrays;
  const Coefficients k = coefficients;
  const auto load = [&](std::size_t x_array, std::size_t q) {
    return Vec3{s[x_array][q], s[x_array + 1][q], s[x_array + 2][q]};
  };
#pragma GCC ivdep
  for (std::size_t p = begin; p < end; ++p) {
    const std::size_t west = p - 1;
    const std::size_t north = p - cols;
    const Vec3 v{s[kVelocityX][p], s[kVelocityY][p], s[kVelocityZ][p]};
    Vec3 f = mass[p] * k.gravity - k.drag * v;
    f += s[kEastTension][p] * load(kEastX, p);
    f -= s[kEastTension][west] * load(kEastX, west);
    f += s[kSouthTension][p] * load(kSouthX, p);
    f -= s[kSouthTension][north] * load(kSouthX, north);
    f -= (load(kToEastX, p) + load(kToSouthX, p)) + (load(kToWestX, p) + load(kToNorthX, p));
    f += (load(kToWestX, p + 1) + load(kToEastX, west)) + (load(kToNorthX, p + cols) + load(kToSouthX, north));
    force[p] = f;
  }
}

}  // namespace

double LatticeKernel::evaluate(const ClothModel& model, std::span<const Vec3> position, std::span<const Vec3> velocity,
                               std::uint32_t terms, int threads, std::span<Vec3> force) {
  CLOTHSIM_ASSERT(active_, "LatticeKernel::prepare() accepted the model");
  CLOTHSIM_ASSERT(model.rows == rows_ && model.cols == cols_ && force.size() == model.particle_count(),
                  "the kernel was prepared for this model");
  if (model.revision != revision_) refresh(model);
  const auto on = [&](ForceTerms term) { return (terms & term) != 0 ? 1.0 : 0.0; };
  const double damped = on(kSpringDamping);
  Coefficients k;
  k.connector_elastic = on(kConnectorSprings);
  k.connector_damped = k.connector_elastic * damped;
  k.adjacent_elastic = on(kAdjacentRadialSprings);
  k.adjacent_damped = k.adjacent_elastic * damped;
  k.opposite_elastic = on(kOppositeRadialSprings);
  k.opposite_damped = k.opposite_elastic * damped;
  k.gravity = (terms & kGravity) != 0 ? model.environment.gravity : Vec3{};
  k.drag = (terms & kAirDrag) != 0 ? model.environment.air_drag : 0.0;
  if (uniform_) {
    k.connector_stiffness = family_[0].stiffness;
    k.connector_damping = family_[0].damping;
    k.connector_rest_length = family_[0].rest;
    k.adjacent_stiffness = family_[1].stiffness;
    k.adjacent_damping = family_[1].damping;
    k.adjacent_rest_angle = family_[1].rest;
    k.opposite_stiffness = family_[2].stiffness;
    k.opposite_damping = family_[2].damping;
    k.opposite_rest_angle = family_[2].rest;
  }

  Arrays s;
  const std::size_t arrays = scratch_.size() / stride_;  // without the parameter arrays on a uniform sheet
  for (std::size_t a = 0; a < kArrayCount; ++a)
    s.a[a] = a < arrays ? scratch_.data() + a * stride_ + padding_ : nullptr;
  const std::size_t cols = static_cast<std::size_t>(cols_);
  const std::size_t rows = static_cast<std::size_t>(rows_);
  const std::size_t n = rows * cols;
  const double* mass = model.particle_mass.data();
  Vec3* out = force.data();

  // The connector pass works row by row (the last column and the last row have no east or south
  // connector). The radial and gather passes need no row structure (borders are zero
  // connectors), so they run over bands of whole rows, at least kBandParticles long: long vector
  // loops, few remainders. The result does not depend on the banding (every particle's values
  // come from the same formulas), only the speed does.
  const std::size_t band_rows = std::max<std::size_t>(1, (kBandParticles + cols - 1) / cols);
  const std::size_t bands = (rows + band_rows - 1) / band_rows;
  const auto pass = [&](int which, std::size_t item) {
    if (which == 0) {
      const std::size_t i = item;
      const std::size_t begin = i * cols;
      const std::size_t end = begin + cols;
      velocity_row(s, velocity.data(), begin, end);
      std::fill(s[kConnectorPower] + begin, s[kConnectorPower] + end, 0.0);
      const auto row = uniform_ ? uniform_connector_row : connector_row;
      row(s, k, position.data(), velocity.data(), begin, end, 1, end - 1, kEastX, s[kConnectorPower]);
      row(s, k, position.data(), velocity.data(), begin, end, cols, i + 1 < rows ? end : begin, kSouthX,
          s[kConnectorPower]);
      return;
    }
    const std::size_t begin = item * band_rows * cols;
    const std::size_t end = std::min(n, begin + band_rows * cols);
    if (which == 1) {
      (uniform_ ? uniform_radial_band : radial_band)(s, k, begin, end, cols);
    } else {
      gather_band(s, k, mass, begin, end, cols, out);
    }
  };
  const auto items = [&](int which) { return which == 0 ? rows : bands; };
  if (threads <= 1) {
    for (int which = 0; which < 3; ++which) {
      for (std::size_t item = 0; item < items(which); ++item) pass(which, item);
    }
  } else {
#pragma omp parallel num_threads(threads)
    for (int which = 0; which < 3; ++which) {
      // The implicit barrier at the end of each loop separates the passes.
      const auto count = static_cast<long long>(items(which));
#pragma omp for schedule(static)
      for (long long item = 0; item < count; ++item) pass(which, static_cast<std::size_t>(item));
    }
  }
  return deterministic_sum(std::span<const double>(s[kPower], n), threads, block_power_);
}

}  // namespace clothsim
