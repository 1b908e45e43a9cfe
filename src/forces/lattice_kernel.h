// The structured force kernel: the whole force function for a rows x cols lattice, intact or
// torn, with any per-spring stiffness, damping and rest values, computed without element lists
// or index indirection.
//
// Why a second path. The general path (connector_springs.cpp, radial_springs.cpp, gather in
// forces.cpp) reads element lists, gathers particles by index, calls std::atan2 and writes one
// force slot per element end: scalar code, about 350 ns per particle. On a lattice every
// particle's neighbours are at fixed offsets (+-1, +-cols) and the loops over a row run over
// contiguous memory, so the compiler can vectorise them. ForceBuffers::resize() picks the kernel
// when the model has the lattice layout that build_lattice() records (ClothModel::layout);
// tests/forces/test_lattice_kernel.cpp checks that both paths agree on random configurations of
// intact, torn and plastic sheets.
//
// Sheets that change (DESIGN.md section 3) stay on this path. Every spring's parameters are
// copied into particle-indexed arrays (east and south connector of each particle: stiffness,
// damping, rest length, 1 if intact; each of its six radial springs: stiffness, damping, rest
// angle), read by the vector loops like the positions. A broken connector is stored like a
// missing one at the border (1/length 0, no tension), so the radial springs that use it drop out
// with no extra test. The copy is refreshed when ClothModel::revision moves: O(springs) between
// steps, nothing per evaluation. Rejected: keeping uniform constants and falling back to the
// general path on the first change (what this kernel did first: a torn sheet then ran about 14
// times slower), and per-family constants with a mask only (plasticity and creasing make every
// rest value different).
//
// Uniform sheets. The 26 parameter arrays are 208 bytes per particle in float64, 45 % of the
// kernel's scratch, and on an intact sheet whose springs all have their family's values (the
// paper's sheets, and a material's) they hold three values per family. There the kernel keeps no parameter arrays
// and reads the family's value instead (uniform(); a second instantiation of the connector and
// radial loops); both forms compute the same products, so they give the same bits. The kernel
// reads the arrays whenever it holds them. prepare() allocates them when the sheet is not
// uniform, or when a law can make it so (SpringLimits::changes_sheet), so that tearing,
// stretching and creasing never allocate inside a step; a uniform sheet that a live edit makes
// non-uniform (a cut in the viewer, a test setting one rest length) gets them when refresh()
// sees the edit, at its next evaluation: the one allocation this kernel makes after prepare().
//
// Passes, each a vectorised loop over particles: row by row for the connectors, over bands of
// whole rows (at least 256 particles, so that short rows still make long vector loops) for the
// other two:
//   1. connectors the east and south connector of each particle, read from the Vec3 position and
//                 velocity arrays: unit vector, 1/length, tension, and the neighbour's relative
//                 velocity, into x/y/z arrays (SoA) for the later passes. The radial springs reuse
//                 them: each connector's square root, division and velocity difference are done
//                 once, not once per spring that uses it;
//   2. radials    the six radial springs centred at each particle; each writes its forces on the
//                 four neighbours into to_east/to_south/to_west/to_north of the centre;
//   3. gather     each particle sums, in a fixed order, gravity, drag, its four connectors'
//                 tensions, minus its own springs' forces on the neighbours, and the forces the
//                 four neighbours' springs put on it.
// Every value is computed by one formula from the same inputs whichever thread computes it, and
// every sum has a fixed order, so the result is bit-for-bit the same for any thread count; the
// passes run in one OpenMP region, rows (bands) split statically between threads, with a barrier
// between passes. Borders need no special code: the arrays have cols + 8 zero entries of padding at
// both ends, a missing or broken connector is stored with 1/length = 0 and tension 0, and a radial
// spring with a missing, broken (or zero-length) connector contributes nothing, exactly like a
// dead or degenerate element of the general path.
//
// Vectorisation. GCC 12 -O3 vectorises the column loops of all three passes (checked with
// -fopt-info-vec: "loop vectorized using 64 byte vectors" in the AVX-512 clone of each, 32 byte
// ones in the AVX2 clone; lattice_kernel.cpp explains the multiversioning) because their bodies
// are straight-line arithmetic with selects: the arctangent is the inline
// vector_math::atan2_first_quadrant instead of std::atan2, and the singular case (a straight or
// folded spring, whose bending plane comes from the motion, element::resolve_singular_directions)
// only marks the particle in the vector loop; marked particles are then recomputed by a scalar
// loop that resolves them. -fno-math-errno and -fno-trapping-math (this file only) let GCC
// if-convert the square roots and divisions; neither changes a value. -ffp-contract=off stays:
// no fused multiply-adds are introduced, and vector lanes round exactly like scalar code.
//
// Precision. In float64 (the default) the kernel differs from the general path only by rounding
// (1/l multiplied instead of dividing by l, the polynomial arctangent instead of libm's), a few
// ulps per force. In float32 (ForceBuffers::precision; `precision float32` or `auto`, sim/backend.h)
// the same loops run on floats, twice the SIMD lanes, while everything that decides accuracy
// stays float64:
//   * the state: each connector's position and velocity differences are taken in double from the
//     float64 state and only then rounded (kEastVelocityX...: the relative velocities are stored
//     per connector), so a sheet 100 m from the origin or falling at 30 m/s loses nothing that a
//     sheet at rest at the origin keeps: the forces' error is relative to the forces, never to the
//     coordinates (the Vulkan backend's float32, whose state is float too, lacks this);
//   * the gather: each particle's force is summed in double, gravity and drag first;
//   * the powers are summed in double, and the integrator's stage sums and error norm are float64.
// What rounds in float is each spring's own force: a few float ulps of it, about 1e-6 of the
// largest force on the sheet (tests/forces/test_float32_forces.cpp, bound 2e-5). RKF45's error
// estimate is then accurate to about h * 1e-6 of the accelerations, which the default tolerances
// of 1e-6 absorb and tighter ones do not (docs/performance.md, "Mixed precision"; `auto`'s rule).
// Two details are float's own: subnormal floats are flushed to zero while the kernel runs (a
// nearly flat sheet makes products of 1e-40, each a microcode assist of ~100 cycles: the float
// kernel ran no faster than the double one before this), and a radial spring counts as straight
// or folded below sin(theta) = 1e-6 instead of 1e-12 (lattice_spring.h, SingularLimits), where
// float's unit vectors stop defining its bending plane. The float64 results are unchanged by a bit
// by all of this.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#include "core/precision.h"
#include "core/vec3.h"
#include "model/cloth_model.h"

namespace clothsim {

// Floating-point operations per particle of one evaluation, for the achieved rate that
// `clothsim bench` reports against the machine's peak (perf/suite.h). Counted in
// lattice_kernel.cpp for an interior particle, on the vector path (both sides of every select
// are computed, and counted); negations, absolute values, comparisons and selects not counted,
// compile-time constants folded:
//   connectors (connector_row_of), 2 per particle, 28 each: difference 3, dot 5, u = e / l 3,
//     relative velocity 3 (stored: the radial springs of both ends read it) and its dot 5,
//     damping 1, tension 5, damping power 3; and 1 division and 1 square root each;
//   radial springs (radial_spring, spring_at), 6 per particle, 106 each: two cross products for
//     n and the two w 27, dot and norm 10, atan2_first_quadrant 27 (reduction 4, z 1, numerator
//     polynomial 8, denominator 9, last terms 5), the angle ratio and its series 6, rest-angle
//     term 1, stiffness per length and gradients 4, angle rate 12, torque 1, elastic term 2, the
//     two forces 12, power 1, switches 2; and 3 divisions and 1 square root each;
//   per particle besides: the sums into the four neighbours 24 and the power 6
//     (radial_particle), the gather 57 (gravity and drag 9, four tensions 24, own and
//     neighbours' spring forces 24), the damping power's sum 1.
// 56 + 636 + 88 = 780 additions and multiplications, 20 divisions and 8 square roots: 808
// operations, each division and square root counted as one (as LINPACK counts them; they take
// many cycles each, so the peak of additions and multiplications is out of reach). (820 until
// issue 12: the arms' four relative velocities, 12, were differences in the radial pass; they are
// now the connectors' own, stored, and the west and north arms negate them.) The same count in
// float32; the float32 kernel's conversions to and from double are not counted.
inline constexpr double kLatticeKernelFlopsPerParticle = 808.0;

// Scratch memory of the structured kernel: padded SoA arrays, allocated by prepare().
class LatticeKernel {
 public:
  // Sizes the scratch for `model` and copies its per-spring parameters, if the model has the
  // lattice layout (ClothModel::layout, recorded by build_lattice; torn, plastic and creased
  // sheets keep it); false (and no scratch) otherwise. `precision`: the arithmetic of the springs
  // (see "Precision" at the top of this file).
  bool prepare(const ClothModel& model, Precision precision = Precision::float64);
  bool active() const { return active_; }
  Precision precision() const { return precision_; }
  // True when the kernel reads one value per family instead of the parameter arrays: every
  // connector is intact, every spring has its family's stiffness, damping and rest value, and
  // the kernel holds no arrays (see the top of this file).
  bool uniform() const { return uniform_; }

  // The force function of forces.h for the prepared lattice; returns the spring damping power
  // (W). `force` [particle_count()]. When the model's revision has moved since the parameters
  // were copied (an event, a live edit), copies them again first: O(springs), no allocation.
  double evaluate(const ClothModel& model, std::span<const Vec3> position, std::span<const Vec3> velocity,
                  std::uint32_t terms, int threads, std::span<Vec3> force);

  // Bytes of scratch memory held.
  std::size_t bytes() const {
    return scratch64_.capacity() * sizeof(double) + scratch32_.capacity() * sizeof(float) +
           block_power_.capacity() * sizeof(double);
  }
  // The bytes bytes() reports after prepare() for the lattice build_lattice() makes with `counts`,
  // with the parameter arrays or without them (a uniform sheet whose limits are all infinite; see
  // the top of this file), in `precision` (the memory estimate, sim/memory_estimate.h).
  static std::size_t bytes_for(const LatticeCounts& counts, bool parameter_arrays,
                               Precision precision = Precision::float64);

 private:
  template <typename Real>
  double evaluate_in(const ClothModel& model, std::span<const Vec3> position, std::span<const Vec3> velocity,
                     std::uint32_t terms, int threads, std::span<Vec3> force);
  // The scratch of precision Real: scratch64_ or scratch32_ (the other stays empty).
  template <typename Real>
  std::vector<Real>& scratch() {
    if constexpr (std::is_same_v<Real, double>) {
      return scratch64_;
    } else {
      return scratch32_;
    }
  }
  // Reals in the scratch of the current precision.
  std::size_t scratch_size() const {
    return precision_ == Precision::float64 ? scratch64_.size() : scratch32_.size();
  }
  // Resizes the scratch of the current precision to `arrays` arrays, new entries zero.
  void resize_scratch(std::size_t arrays);
  template <typename Real>
  void copy_parameters(const ClothModel& model);
  // Takes the model's parameters: one value per family on a uniform sheet, else every spring's
  // stiffness, damping, rest value and liveness into the padded arrays.
  void refresh(const ClothModel& model);
  // Every connector intact, and every spring of a family with the same stiffness, damping and
  // rest value.
  static bool is_uniform(const ClothModel& model);
  // Zero entries before and after each array, and Reals per array (padding + particles +
  // padding, rounded up to whole 64-byte lines of floats).
  static std::size_t padding(std::size_t cols) { return cols + 8; }
  static std::size_t stride(std::size_t particles, std::size_t cols) {
    return (particles + 2 * padding(cols) + 15) / 16 * 16;
  }

  // One family's parameters while the sheet is uniform.
  struct FamilyValues {
    double stiffness = 0.0;
    double damping = 0.0;
    double rest = 0.0;  // rest length (m) or rest angle (rad)
    bool operator==(const FamilyValues&) const = default;
  };

  bool active_ = false;
  bool uniform_ = false;
  Precision precision_ = Precision::float64;
  std::array<FamilyValues, 3> family_{};  // connector, adjacent, opposite (uniform sheets)
  int rows_ = 0;
  int cols_ = 0;
  std::size_t padding_ = 0;     // zero entries before and after each array
  std::size_t stride_ = 0;      // Reals per array (padding + particles + padding, rounded up)
  std::uint64_t revision_ = 0;  // ClothModel::revision the parameters were copied at
  // kArrayCount arrays of stride_ Reals, the parameter arrays last and only while needed
  // (lattice_kernel_layout.h): in double, or in float for float32 forces.
  std::vector<double> scratch64_;
  std::vector<float> scratch32_;
  std::vector<double> block_power_;
};

}  // namespace clothsim
