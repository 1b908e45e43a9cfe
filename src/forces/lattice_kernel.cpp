// The structured force kernel for a lattice, intact or torn; the design is in lattice_kernel.h.
#include "forces/lattice_kernel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <type_traits>
#include <utility>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

#include "core/assert.h"
#include "core/multiversion.h"
#include "forces/element.h"
#include "forces/forces.h"
#include "forces/lattice_kernel_layout.h"
#include "forces/lattice_spring.h"

namespace clothsim {
namespace {

using namespace lattice_layout;

// Flushes subnormal results and inputs to zero on this thread while it lives (x86's FTZ and DAZ
// bits), when `on`; restores the thread's mode after. For float32 forces: a nearly flat sheet
// makes products like sin(theta)^2 of 1e-40, below float's normal range, and each operation on
// a subnormal float costs the CPU a microcode assist of about a hundred cycles. Values that small
// are far below anything the float32 springs resolve (forces/lattice_kernel.h, "Precision"), so
// flushing them changes no force that matters. float64 forces never flush.
class FlushSubnormals {
 public:
  explicit FlushSubnormals(bool on) {
#if defined(__SSE2__)
    if (on) {
      saved_ = _mm_getcsr();
      _mm_setcsr(saved_ | kFlushToZero | kDenormalsAreZero);
      active_ = true;
    }
#else
    (void)on;
#endif
  }
  ~FlushSubnormals() {
#if defined(__SSE2__)
    if (active_) _mm_setcsr(saved_);
#endif
  }
  FlushSubnormals(const FlushSubnormals&) = delete;
  FlushSubnormals& operator=(const FlushSubnormals&) = delete;

 private:
  static constexpr unsigned kFlushToZero = 0x8000;       // MXCSR.FTZ
  static constexpr unsigned kDenormalsAreZero = 0x0040;  // MXCSR.DAZ
  unsigned saved_ = 0;
  bool active_ = false;
};

// Particles per band of the radial and gather passes (at least; bands are whole rows).
constexpr std::size_t kBandParticles = 256;

// The row and band functions are compiled for AVX-512, AVX2 and baseline x86-64 and chosen at
// load time (core/multiversion.h).

// Switches of one evaluation: 1 for a force term that is on, 0 for one that is off, multiplied
// onto the per-spring constants (multiplying by 1 is exact, so a term that is on gives the same
// bits as without the switch). On a uniform sheet, also the one value of each parameter of each
// family, read instead of the parameter arrays: the products are the same as with the arrays,
// so both forms give the same bits. In the precision of the forces, but for gravity and drag,
// which the gather adds in double.
template <typename Real>
struct Coefficients {
  Real connector_elastic = 0;
  Real connector_damped = 0;
  Real adjacent_elastic = 0;
  Real adjacent_damped = 0;
  Real opposite_elastic = 0;
  Real opposite_damped = 0;
  Vec3 gravity;
  double drag = 0.0;
  // Uniform sheets only.
  Real connector_stiffness = 0;
  Real connector_damping = 0;
  Real connector_rest_length = 0;
  Real connector_fade_length = 0;  // element::kRadialFadeFraction times the original length
  Real adjacent_stiffness = 0;
  Real adjacent_damping = 0;
  Real adjacent_rest_angle = 0;
  Real opposite_stiffness = 0;
  Real opposite_damping = 0;
  Real opposite_rest_angle = 0;
};

// Pointers into the scratch, offset past the padding: index p is particle p, p - 1 its west
// neighbour, p - cols its north neighbour (or padding / the previous row's last particle, whose
// east connector does not exist: either way a zero connector).
template <typename Real>
struct Arrays {
  Real* a[kArrayCount];
  Real* operator[](std::size_t k) const { return a[k]; }
};

using lattice_spring::RadialResult;
template <typename Real>
using Vector = lattice_spring::Vector<Real>;

// A Vec3 of the float64 state in the precision of the forces.
template <typename Real>
[[gnu::always_inline]] inline Vector<Real> to_real(const Vec3& a) {
  return {static_cast<Real>(a.x), static_cast<Real>(a.y), static_cast<Real>(a.z)};
}

// Connector from each particle p in [begin, missing_from) to p + offset (east: 1, south: cols),
// read straight from the Vec3 arrays; particles from `missing_from` to `end` have none (the last
// column has no east connector, the last row no south one). kUniform: the parameters are the
// family's (Coefficients), every connector intact. The differences of positions and velocities
// are taken in double, then rounded to Real.
template <typename Real, bool kUniform>
[[gnu::always_inline]] inline void connector_row_of(const Arrays<Real>& s, const Coefficients<Real>& k,
                                                    const Vec3* __restrict x, const Vec3* __restrict v,
                                                    std::size_t begin, std::size_t end, std::size_t offset,
                                                    std::size_t missing_from, std::size_t ux_array,
                                                    Real* __restrict power) {
  Real* __restrict ux = s[ux_array];
  Real* __restrict uy = s[ux_array + 1];
  Real* __restrict uz = s[ux_array + 2];
  Real* __restrict inverse_length = s[ux_array + 3];
  Real* __restrict tension = s[ux_array + 4];
  Real* __restrict vx = s[ux_array + 5];
  Real* __restrict vy = s[ux_array + 6];
  Real* __restrict vz = s[ux_array + 7];
  // The parameter arrays of this direction (east and south are laid out alike); null when uniform.
  const std::size_t parameters = ux_array == kEastX ? kEastStiffness : kSouthStiffness;
  const Real* __restrict stiffness = kUniform ? nullptr : s[parameters];
  const Real* __restrict damping = kUniform ? nullptr : s[parameters + 1];
  const Real* __restrict rest_length = kUniform ? nullptr : s[parameters + 2];
  const Real* __restrict live = kUniform ? nullptr : s[parameters + 3];
  const Real* __restrict fade_length = kUniform ? nullptr : s[parameters + 4];
  Real* __restrict fade = s[ux_array + 8];
  Real* __restrict fade_slope = s[ux_array + 9];
  const Real elastic = k.connector_elastic;
  const Real damped = k.connector_damped;
  const Real zero = 0;
#pragma GCC ivdep
  for (std::size_t p = begin; p < missing_from; ++p) {
    const Vector<Real> e = to_real<Real>(x[p + offset] - x[p]);
    const Vector<Real> relative_velocity = to_real<Real>(v[p + offset] - v[p]);
    const Real length = std::sqrt(dot(e, e));
    // A broken connector is stored like a missing one: 1/length = 0 and no tension, which also
    // switches off the radial springs that use it.
    const bool exists = length > zero && (kUniform || live[p] > zero);
    const Real inverse = exists ? Real(1) / length : zero;
    const Vector<Real> u = inverse * e;
    const Real rate = dot(relative_velocity, u);
    const Real c = damped * (kUniform ? k.connector_damping : damping[p]);
    const Real t = elastic * (kUniform ? k.connector_stiffness : stiffness[p]) *
                       (length - (kUniform ? k.connector_rest_length : rest_length[p])) +
                   c * rate;
    ux[p] = u.x;
    uy[p] = u.y;
    uz[p] = u.z;
    inverse_length[p] = inverse;
    tension[p] = exists ? t : zero;
    vx[p] = relative_velocity.x;
    vy[p] = relative_velocity.y;
    vz[p] = relative_velocity.z;
    power[p] += exists ? -c * rate * rate : zero;
    const lattice_spring::Fade<Real> f =
        lattice_spring::arm_fade(length, kUniform ? k.connector_fade_length : fade_length[p]);
    fade[p] = exists ? f.value : Real(1);
    fade_slope[p] = exists ? f.slope : zero;
  }
  // No connector from the last column eastwards, or from the last row southwards.
  for (std::size_t p = missing_from; p < end; ++p) {
    ux[p] = uy[p] = uz[p] = inverse_length[p] = tension[p] = vx[p] = vy[p] = vz[p] = fade_slope[p] = zero;
    fade[p] = Real(1);
  }
}

// The multiversioned entry points (core/multiversion.h takes no templates): one per precision
// and form, and a template that picks it. Everything they call is always_inline: with both
// precisions in this file, GCC's inliner otherwise runs out of its growth budget and leaves small
// calls (dot, cross, the arctangent) inside the loops, which then do not vectorise.
#define CLOTHSIM_CONNECTOR_ROW(name, Real, kUniform)                                                                \
  CLOTHSIM_MULTIVERSION void name(const Arrays<Real>& s, const Coefficients<Real>& k, const Vec3* __restrict x,     \
                                  const Vec3* __restrict v, std::size_t begin, std::size_t end, std::size_t offset, \
                                  std::size_t missing_from, std::size_t ux_array, Real* __restrict power) {         \
    connector_row_of<Real, kUniform>(s, k, x, v, begin, end, offset, missing_from, ux_array, power);                \
  }
CLOTHSIM_CONNECTOR_ROW(connector_row_64, double, false)
CLOTHSIM_CONNECTOR_ROW(uniform_connector_row_64, double, true)
CLOTHSIM_CONNECTOR_ROW(connector_row_32, float, false)
CLOTHSIM_CONNECTOR_ROW(uniform_connector_row_32, float, true)
#undef CLOTHSIM_CONNECTOR_ROW

template <typename Real>
void connector_row(bool uniform, const Arrays<Real>& s, const Coefficients<Real>& k, const Vec3* x, const Vec3* v,
                   std::size_t begin, std::size_t end, std::size_t offset, std::size_t missing_from,
                   std::size_t ux_array, Real* power) {
  if constexpr (std::is_same_v<Real, double>) {
    (uniform ? uniform_connector_row_64 : connector_row_64)(s, k, x, v, begin, end, offset, missing_from, ux_array,
                                                            power);
  } else {
    (uniform ? uniform_connector_row_32 : connector_row_32)(s, k, x, v, begin, end, offset, missing_from, ux_array,
                                                            power);
  }
}

// A connector of particle p seen from p: unit vector towards the neighbour, 1/length, the fade of
// the radial springs on it, and the neighbour's velocity relative to p's. Directions: 0 east, 1 south, 2 west, 3 north;
// west and north are the neighbour's east and south connector reversed (negation is exact, so they are the same values
// as differences taken from p's side).
template <typename Real>
struct Arm {
  Vector<Real> unit;
  Real inverse_length = 0;
  lattice_spring::Fade<Real> fade;
  Vector<Real> relative_velocity;
};

template <typename Real, int kDirection>
[[gnu::always_inline]] inline Arm<Real> arm(const Arrays<Real>& s, std::size_t p, std::size_t cols) {
  constexpr std::size_t kFirst = kDirection == 0 || kDirection == 2 ? kEastX : kSouthX;
  const std::size_t q = kDirection == 0 || kDirection == 1 ? p : kDirection == 2 ? p - 1 : p - cols;
  const Vector<Real> unit{s[kFirst][q], s[kFirst + 1][q], s[kFirst + 2][q]};
  const Vector<Real> velocity{s[kFirst + 5][q], s[kFirst + 6][q], s[kFirst + 7][q]};
  Arm<Real> out;
  out.inverse_length = s[kFirst + 3][q];
  out.fade = {s[kFirst + 8][q], s[kFirst + 9][q]};
  if constexpr (kDirection < 2) {
    out.unit = unit;
    out.relative_velocity = velocity;
  } else {
    out.unit = -unit;
    out.relative_velocity = -velocity;
  }
  return out;
}

// Radial spring kPair of particle p (model/lattice_springs.inc), between its arms
// kRadialArmB[kPair] and kRadialArmC[kPair], with its own stiffness, damping and rest angle
// (kUniform: its family's). On a uniform sheet a spring that does not exist (at a border) has the
// family's values, not zeros, and contributes nothing all the same: one of its arms has 1/length 0.
template <typename Real, bool kUniform, bool kResolveSingular, bool kFade, std::size_t kPair>
[[gnu::always_inline]] inline RadialResult<Real> spring_at(const Arrays<Real>& s, const Coefficients<Real>& k,
                                                           std::size_t p, std::size_t cols) {
  constexpr bool kOpposite = radial_pair_is_opposite(kPair);
  const Arm<Real> b = arm<Real, kRadialArmB[kPair]>(s, p, cols);
  const Arm<Real> c = arm<Real, kRadialArmC[kPair]>(s, p, cols);
  const Real elastic = kOpposite ? k.opposite_elastic : k.adjacent_elastic;
  const Real damped = kOpposite ? k.opposite_damped : k.adjacent_damped;
  Real stiffness = 0;
  Real damping = 0;
  Real rest_angle = 0;
  if constexpr (kUniform) {
    stiffness = kOpposite ? k.opposite_stiffness : k.adjacent_stiffness;
    damping = kOpposite ? k.opposite_damping : k.adjacent_damping;
    rest_angle = kOpposite ? k.opposite_rest_angle : k.adjacent_rest_angle;
  } else {
    stiffness = s[kRadialStiffness + kPair][p];
    damping = s[kRadialDamping + kPair][p];
    rest_angle = s[kRadialRestAngle + kPair][p];
  }
  return lattice_spring::radial_spring<Real, kResolveSingular, kFade>(
      b.unit, b.inverse_length, b.fade, c.unit, c.inverse_length, c.fade, b.relative_velocity, c.relative_velocity,
      elastic * stiffness, damped * damping, rest_angle);
}

// The force the radial springs centred at a particle exert on the neighbour along an arm is the
// sum of the ends of the springs there, in the springs' order: three terms (each arm is an end of
// two adjacent springs and one opposite spring), each spring `pair`'s b end (b) or c end.
struct ArmTerm {
  std::size_t pair = 0;
  bool b = false;
};
constexpr std::array<ArmTerm, 3> arm_terms(int arm) {
  std::array<ArmTerm, 3> terms{};
  std::size_t count = 0;
  for (std::size_t pair = 0; pair < static_cast<std::size_t>(kRadialsPerParticle); ++pair) {
    if (kRadialArmB[pair] == arm || kRadialArmC[pair] == arm) terms.at(count++) = {pair, kRadialArmB[pair] == arm};
  }
  return terms;
}

template <typename Real>
using ParticleSprings = std::array<RadialResult<Real>, static_cast<std::size_t>(kRadialsPerParticle)>;

template <typename Real, int kArm>
[[gnu::always_inline]] inline Vector<Real> force_on_arm(const ParticleSprings<Real>& springs) {
  constexpr std::array<ArmTerm, 3> kTerms = arm_terms(kArm);
  static_assert(kTerms[0].pair < kTerms[1].pair && kTerms[1].pair < kTerms[2].pair, "three springs end on each arm");
  const auto end = [&](const ArmTerm& term) { return term.b ? springs[term.pair].on_b : springs[term.pair].on_c; };
  return end(kTerms[0]) + end(kTerms[1]) + end(kTerms[2]);
}

template <typename Real, bool kUniform, bool kFade, std::size_t... kPair>
[[gnu::always_inline]] inline ParticleSprings<Real> springs_at(const Arrays<Real>& s, const Coefficients<Real>& k,
                                                               std::size_t p, std::size_t cols,
                                                               std::index_sequence<kPair...>) {
  return {spring_at<Real, kUniform, false, kFade, kPair>(s, k, p, cols)...};
}

// The six radial springs centred at particle p, written as forces on its four neighbours; each
// neighbour's sum and the power are accumulated in the springs' order (spring_row repeats
// exactly these sums). Returns a positive number if one of the springs is singular.
template <typename Real, bool kUniform, bool kFade>
[[gnu::always_inline]] inline Real radial_particle(const Arrays<Real>& s, const Coefficients<Real>& k, std::size_t p,
                                                   std::size_t cols) {
  const ParticleSprings<Real> r = springs_at<Real, kUniform, kFade>(
      s, k, p, cols, std::make_index_sequence<static_cast<std::size_t>(kRadialsPerParticle)>());
  const Vector<Real> to_east = force_on_arm<Real, 0>(r);
  const Vector<Real> to_south = force_on_arm<Real, 1>(r);
  const Vector<Real> to_west = force_on_arm<Real, 2>(r);
  const Vector<Real> to_north = force_on_arm<Real, 3>(r);
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
  s[kPower][p] = s[kConnectorPower][p] + r[0].power + r[1].power + r[2].power + r[3].power + r[4].power + r[5].power;
  return std::max(std::max(std::max(r[0].singular, r[1].singular), std::max(r[2].singular, r[3].singular)),
                  std::max(r[4].singular, r[5].singular));
}

// The to_<direction> x array of each direction.
constexpr std::array<std::size_t, 4> kToArray = {kToEastX, kToSouthX, kToWestX, kToNorthX};

// Spring kPair of every particle of a band, added into the neighbours' sums in the order of
// radial_particle (a spring that is the first term of a neighbour's sum starts it). kResolve:
// singular springs resolved (their bending plane from the motion), which gives every other spring
// the same values as without it; without, returns 1 if a spring was singular (its values then
// meaningless). One spring per loop keeps the body small enough for GCC to if-convert and
// vectorise it; inlined, so it is compiled into each clone of radial_band.
template <typename Real, bool kUniform, bool kFade, bool kResolve, std::size_t kPair>
[[gnu::always_inline]] inline int spring_row(const Arrays<Real>& s, const Coefficients<Real>& k, std::size_t begin,
                                             std::size_t end, std::size_t cols) {
  constexpr int kB = kRadialArmB[kPair];
  constexpr int kC = kRadialArmC[kPair];
  constexpr bool kFirstB = arm_terms(kB)[0].pair == kPair;
  constexpr bool kFirstC = arm_terms(kC)[0].pair == kPair;
  Real* __restrict bx = s[kToArray[kB]];
  Real* __restrict by = s[kToArray[kB] + 1];
  Real* __restrict bz = s[kToArray[kB] + 2];
  Real* __restrict cx = s[kToArray[kC]];
  Real* __restrict cy = s[kToArray[kC] + 1];
  Real* __restrict cz = s[kToArray[kC] + 2];
  Real* __restrict power = s[kPower];
  const Real zero = 0;
  int singular = 0;
#pragma GCC ivdep
  for (std::size_t p = begin; p < end; ++p) {
    const RadialResult<Real> r = spring_at<Real, kUniform, kResolve, kFade, kPair>(s, k, p, cols);
    bx[p] = (kFirstB ? zero : bx[p]) + r.on_b.x;
    by[p] = (kFirstB ? zero : by[p]) + r.on_b.y;
    bz[p] = (kFirstB ? zero : bz[p]) + r.on_b.z;
    cx[p] = (kFirstC ? zero : cx[p]) + r.on_c.x;
    cy[p] = (kFirstC ? zero : cy[p]) + r.on_c.y;
    cz[p] = (kFirstC ? zero : cz[p]) + r.on_c.z;
    power[p] += r.power;
    if constexpr (!kResolve) singular |= r.singular > zero ? 1 : 0;
  }
  return singular;
}

// Springs kPair... of every particle of a band, one pair after another; returns 1 if one was
// singular (!kResolve).
template <typename Real, bool kUniform, bool kFade, bool kResolve, std::size_t... kPair>
[[gnu::always_inline]] inline int spring_rows(const Arrays<Real>& s, const Coefficients<Real>& k, std::size_t begin,
                                              std::size_t end, std::size_t cols, std::index_sequence<kPair...>) {
  return (spring_row<Real, kUniform, kFade, kResolve, kPair>(s, k, begin, end, cols) | ...);
}

// The radial springs of a band with a singular spring, spring by spring: the adjacent ones
// (pairs 0 to 3, singular only where the sheet is folded flat) first without resolving, the
// opposite ones (straight on every flat part of the sheet) resolved; the adjacent ones again,
// resolved, if one was singular after all (each adjacent spring's first term of a sum starts it).
template <typename Real, bool kUniform, bool kFade>
[[gnu::always_inline]] inline void resolve_band(const Arrays<Real>& s, const Coefficients<Real>& k, std::size_t begin,
                                                std::size_t end, std::size_t cols) {
  static_assert(!radial_pair_is_opposite(0) && !radial_pair_is_opposite(1) && !radial_pair_is_opposite(2) &&
                    !radial_pair_is_opposite(3) && radial_pair_is_opposite(4) && radial_pair_is_opposite(5) &&
                    kRadialsPerParticle == 6,
                "the adjacent springs come first");
  static_assert(
      arm_terms(0)[0].pair < 4 && arm_terms(1)[0].pair < 4 && arm_terms(2)[0].pair < 4 && arm_terms(3)[0].pair < 4,
      "an adjacent spring starts each arm's sum");
  Real* __restrict power = s[kPower];
  const Real* __restrict connector_power = s[kConnectorPower];
  for (std::size_t p = begin; p < end; ++p) power[p] = connector_power[p];
  constexpr auto kAdjacent = std::index_sequence<0, 1, 2, 3>();
  if (spring_rows<Real, kUniform, kFade, false>(s, k, begin, end, cols, kAdjacent) != 0) {
    for (std::size_t p = begin; p < end; ++p) power[p] = connector_power[p];
    spring_rows<Real, kUniform, kFade, true>(s, k, begin, end, cols, kAdjacent);
  }
  spring_rows<Real, kUniform, kFade, true>(s, k, begin, end, cols, std::index_sequence<4, 5>());
}

// Whether an arm of a particle in [begin, end) is inside the fade: its east and south connectors,
// and its west and north ones (the neighbours' east and south).
template <typename Real>
[[gnu::always_inline]] inline bool band_fades(const Arrays<Real>& s, std::size_t begin, std::size_t end,
                                              std::size_t cols) {
  const Real* __restrict east = s[kEastFade];
  const Real* __restrict south = s[kSouthFade];
  int fading = 0;
  for (std::size_t p = begin > 0 ? begin - 1 : 0; p < end; ++p) fading |= east[p] < Real(1) ? 1 : 0;
  for (std::size_t p = begin >= cols ? begin - cols : 0; p < end; ++p) fading |= south[p] < Real(1) ? 1 : 0;
  return fading != 0;
}

// Whether one of the opposite radial springs centred at the particles of [begin, end) is
// singular (its arms' sin(theta) below SingularLimits::sine, as radial_spring tests it): a
// straight spring, as on every flat part of a sheet. Only the two springs' cross products, a
// twentieth of the springs' work. (An adjacent spring is singular only where the sheet is folded
// flat at its particle; radial_band_with finds it in the springs' own test.)
template <typename Real>
[[gnu::always_inline]] inline bool band_is_straight(const Arrays<Real>& s, std::size_t begin, std::size_t end,
                                                    std::size_t cols) {
  using Limits = lattice_spring::SingularLimits<Real>;
  const Real zero = 0;
  const auto straight = [&](const Arm<Real>& b, const Arm<Real>& c) {
    const Vector<Real> n = lattice_spring::cross(b.unit, c.unit);
    const bool exists = std::min(b.inverse_length, c.inverse_length) > zero;
    return exists && std::sqrt(dot(n, n)) < Limits::sine ? 1 : 0;
  };
  int singular = 0;
#pragma GCC ivdep
  for (std::size_t p = begin; p < end; ++p) {
    singular |= straight(arm<Real, 0>(s, p, cols), arm<Real, 2>(s, p, cols)) |
                straight(arm<Real, 1>(s, p, cols), arm<Real, 3>(s, p, cols));
  }
  return singular != 0;
}

template <typename Real, bool kUniform, bool kFade>
[[gnu::always_inline]] inline void radial_band_with(const Arrays<Real>& s, const Coefficients<Real>& k,
                                                    std::size_t begin, std::size_t end, std::size_t cols) {
  // A band whose first row has a straight spring goes to the springs one by one at once: flat
  // parts of a sheet are straight throughout. Any other band finds its singular springs in the
  // springs' own test. Either way a band with a singular spring takes resolve_band, whose
  // values do not depend on the way it came.
  int any_singular = band_is_straight(s, begin, std::min(end, begin + cols), cols) ? 1 : 0;
  if (any_singular == 0) {
    Real* __restrict singular = s[kSingular];
#pragma GCC ivdep
    for (std::size_t p = begin; p < end; ++p) {
      singular[p] = radial_particle<Real, kUniform, kFade>(s, k, p, cols);
      any_singular |= singular[p] > Real(0) ? 1 : 0;
    }
  }
  if (any_singular != 0) {
    // A straight or folded spring in this band (a flat sheet, at the start of most runs; a
    // symmetry line): the band spring by spring with the bending plane taken from the motion
    // where it is undefined. Particles without a singular spring get the values radial_particle
    // gives them.
    resolve_band<Real, kUniform, kFade>(s, k, begin, end, cols);
  }
}

template <typename Real, bool kUniform>
[[gnu::always_inline]] inline void radial_band_of(const Arrays<Real>& arrays, const Coefficients<Real>& coefficients,
                                                  std::size_t begin, std::size_t end, std::size_t cols) {
  // Local copies, so that the compiler sees the array pointers and coefficients as loop invariant.
  const Arrays<Real> s = arrays;
  const Coefficients<Real> k = coefficients;
  // The fade of vanishing arms costs a seventh of the springs' work and acts only where a
  // connector is collapsing: a band without one takes the loops without it (the same bits).
  if (band_fades(s, begin, end, cols)) {
    radial_band_with<Real, kUniform, true>(s, k, begin, end, cols);
  } else {
    radial_band_with<Real, kUniform, false>(s, k, begin, end, cols);
  }
}

#define CLOTHSIM_RADIAL_BAND(name, Real, kUniform)                                                    \
  CLOTHSIM_MULTIVERSION void name(const Arrays<Real>& arrays, const Coefficients<Real>& coefficients, \
                                  std::size_t begin, std::size_t end, std::size_t cols) {             \
    radial_band_of<Real, kUniform>(arrays, coefficients, begin, end, cols);                           \
  }
CLOTHSIM_RADIAL_BAND(radial_band_64, double, false)
CLOTHSIM_RADIAL_BAND(uniform_radial_band_64, double, true)
CLOTHSIM_RADIAL_BAND(radial_band_32, float, false)
CLOTHSIM_RADIAL_BAND(uniform_radial_band_32, float, true)
#undef CLOTHSIM_RADIAL_BAND

template <typename Real>
void radial_band(bool uniform, const Arrays<Real>& s, const Coefficients<Real>& k, std::size_t begin, std::size_t end,
                 std::size_t cols) {
  if constexpr (std::is_same_v<Real, double>) {
    (uniform ? uniform_radial_band_64 : radial_band_64)(s, k, begin, end, cols);
  } else {
    (uniform ? uniform_radial_band_32 : radial_band_32)(s, k, begin, end, cols);
  }
}

// Each particle's force, summed in double whatever the precision of the springs: gravity and
// drag (exact inputs, and the largest terms of a hanging sheet), then the connectors' tensions
// and the radial springs' forces, each read and widened to double.
template <typename Real>
[[gnu::always_inline]] inline void gather_band_of(const Arrays<Real>& arrays, const Coefficients<Real>& coefficients,
                                                  const double* __restrict mass, const Vec3* __restrict velocity,
                                                  std::size_t begin, std::size_t end, std::size_t cols,
                                                  Vec3* __restrict force) {
  const Arrays<Real> s = arrays;
  const Coefficients<Real> k = coefficients;
  const auto load = [&](std::size_t x_array, std::size_t q) {
    return Vec3{static_cast<double>(s[x_array][q]), static_cast<double>(s[x_array + 1][q]),
                static_cast<double>(s[x_array + 2][q])};
  };
  const auto tension = [&](std::size_t array, std::size_t q) { return static_cast<double>(s[array][q]); };
#pragma GCC ivdep
  for (std::size_t p = begin; p < end; ++p) {
    const std::size_t west = p - 1;
    const std::size_t north = p - cols;
    Vec3 f = mass[p] * k.gravity - k.drag * velocity[p];
    f += tension(kEastTension, p) * load(kEastX, p);
    f -= tension(kEastTension, west) * load(kEastX, west);
    f += tension(kSouthTension, p) * load(kSouthX, p);
    f -= tension(kSouthTension, north) * load(kSouthX, north);
    f -= (load(kToEastX, p) + load(kToSouthX, p)) + (load(kToWestX, p) + load(kToNorthX, p));
    f += (load(kToWestX, p + 1) + load(kToEastX, west)) + (load(kToNorthX, p + cols) + load(kToSouthX, north));
    force[p] = f;
  }
}

#define CLOTHSIM_GATHER_BAND(name, Real)                                                                             \
  CLOTHSIM_MULTIVERSION void name(const Arrays<Real>& arrays, const Coefficients<Real>& coefficients,                \
                                  const double* __restrict mass, const Vec3* __restrict velocity, std::size_t begin, \
                                  std::size_t end, std::size_t cols, Vec3* __restrict force) {                       \
    gather_band_of<Real>(arrays, coefficients, mass, velocity, begin, end, cols, force);                             \
  }
CLOTHSIM_GATHER_BAND(gather_band_64, double)
CLOTHSIM_GATHER_BAND(gather_band_32, float)
#undef CLOTHSIM_GATHER_BAND

template <typename Real>
void gather_band(const Arrays<Real>& s, const Coefficients<Real>& k, const double* mass, const Vec3* velocity,
                 std::size_t begin, std::size_t end, std::size_t cols, Vec3* force) {
  if constexpr (std::is_same_v<Real, double>) {
    gather_band_64(s, k, mass, velocity, begin, end, cols, force);
  } else {
    gather_band_32(s, k, mass, velocity, begin, end, cols, force);
  }
}

}  // namespace

double LatticeKernel::evaluate(const ClothModel& model, std::span<const Vec3> position, std::span<const Vec3> velocity,
                               std::uint32_t terms, int threads, std::span<Vec3> force) {
  CLOTHSIM_ASSERT(active_, "LatticeKernel::prepare() accepted the model");
  CLOTHSIM_ASSERT(model.rows == rows_ && model.cols == cols_ && force.size() == model.particle_count(),
                  "the kernel was prepared for this model");
  if (model.revision != revision_) refresh(model);
  return precision_ == Precision::float64 ? evaluate_in<double>(model, position, velocity, terms, threads, force)
                                          : evaluate_in<float>(model, position, velocity, terms, threads, force);
}

template <typename Real>
double LatticeKernel::evaluate_in(const ClothModel& model, std::span<const Vec3> position,
                                  std::span<const Vec3> velocity, std::uint32_t terms, int threads,
                                  std::span<Vec3> force) {
  const auto on = [&](ForceTerms term) { return (terms & term) != 0 ? Real(1) : Real(0); };
  const Real damped = on(kSpringDamping);
  Coefficients<Real> k;
  k.connector_elastic = on(kConnectorSprings);
  k.connector_damped = k.connector_elastic * damped;
  k.adjacent_elastic = on(kAdjacentRadialSprings);
  k.adjacent_damped = k.adjacent_elastic * damped;
  k.opposite_elastic = on(kOppositeRadialSprings);
  k.opposite_damped = k.opposite_elastic * damped;
  k.gravity = (terms & kGravity) != 0 ? model.environment.gravity : Vec3{};
  k.drag = (terms & kAirDrag) != 0 ? model.environment.air_drag : 0.0;
  if (uniform_) {
    k.connector_stiffness = static_cast<Real>(family_[0].stiffness);
    k.connector_damping = static_cast<Real>(family_[0].damping);
    k.connector_rest_length = static_cast<Real>(family_[0].rest);
    k.connector_fade_length = static_cast<Real>(element::kRadialFadeFraction * family_[0].original);
    k.adjacent_stiffness = static_cast<Real>(family_[1].stiffness);
    k.adjacent_damping = static_cast<Real>(family_[1].damping);
    k.adjacent_rest_angle = static_cast<Real>(family_[1].rest);
    k.opposite_stiffness = static_cast<Real>(family_[2].stiffness);
    k.opposite_damping = static_cast<Real>(family_[2].damping);
    k.opposite_rest_angle = static_cast<Real>(family_[2].rest);
  }

  std::vector<Real>& scratch = this->scratch<Real>();
  Arrays<Real> s;
  const std::size_t arrays = scratch.size() / stride_;  // without the parameter arrays on a uniform sheet
  for (std::size_t a = 0; a < kArrayCount; ++a) s.a[a] = a < arrays ? scratch.data() + a * stride_ + padding_ : nullptr;
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
      std::fill(s[kConnectorPower] + begin, s[kConnectorPower] + end, Real(0));
      const auto row = [&](std::size_t offset, std::size_t missing_from, std::size_t ux_array) {
        connector_row(uniform_, s, k, position.data(), velocity.data(), begin, end, offset, missing_from, ux_array,
                      s[kConnectorPower]);
      };
      row(1, end - 1, kEastX);
      row(cols, i + 1 < rows ? end : begin, kSouthX);
      return;
    }
    const std::size_t begin = item * band_rows * cols;
    const std::size_t end = std::min(n, begin + band_rows * cols);
    if (which == 1) {
      radial_band(uniform_, s, k, begin, end, cols);
    } else {
      gather_band(s, k, mass, velocity.data(), begin, end, cols, out);
    }
  };
  const auto items = [&](int which) { return which == 0 ? rows : bands; };
  if (threads <= 1) {
    const FlushSubnormals flush(std::is_same_v<Real, float>);
    for (int which = 0; which < 3; ++which) {
      for (std::size_t item = 0; item < items(which); ++item) pass(which, item);
    }
  } else {
#pragma omp parallel num_threads(threads)
    {
      const FlushSubnormals flush(std::is_same_v<Real, float>);
      for (int which = 0; which < 3; ++which) {
        // The implicit barrier at the end of each loop separates the passes.
        const auto count = static_cast<long long>(items(which));
#pragma omp for schedule(static)
        for (long long item = 0; item < count; ++item) pass(which, static_cast<std::size_t>(item));
      }
    }
  }
  return deterministic_sum(std::span<const Real>(s[kPower], n), threads, block_power_);
}

}  // namespace clothsim
