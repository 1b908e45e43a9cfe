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
// Every spring's parameters are copied into particle-indexed arrays (refresh(), when
// ClothModel::revision moves), a broken connector stored like a missing one at the border; on a
// uniform sheet the kernel keeps no arrays and reads each family's value (uniform()), with the
// same bits. prepare() allocates what tearing, stretching and creasing can need, so that they
// never allocate inside a step.
//
// Passes, each a vectorised loop over particles (row by row for the connectors, over bands of
// whole rows for the others):
//   1. connectors the east and south connector of each particle: unit vector, 1/length, tension
//                 and relative velocity, into SoA arrays the radial springs reuse;
//   2. radials    the six radial springs centred at each particle, written as forces on its four
//                 neighbours;
//   3. gather     each particle sums, in a fixed order, gravity, drag, its connectors' tensions and
//                 the radial forces on it.
// Every value comes from one formula whichever thread computes it and every sum has a fixed
// order, so the result is bit-for-bit the same for any thread count. Borders need no special
// code: the arrays are zero-padded, and a missing or broken connector has 1/length = 0.
//
// Precision. In float64 (the default) the kernel differs from the general path only by rounding,
// a few ulps per force. In float32 (ForceBuffers::precision) the same loops run on floats while
// the state's differences, the gather and the powers stay float64, so the forces' error is
// relative to the forces, never to the coordinates.
//
// docs/performance.md ("The lattice kernel in detail") has the parameter arrays and uniform
// sheets, the passes, what makes them vectorise, float32's details and what was rejected.
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
//   connectors (connector_row_of), 2 per particle, 40 each: difference 3, dot 5, u = e / l 3,
//     relative velocity 3 (stored: the radial springs of both ends read it) and its dot 5,
//     damping 1, tension 5, damping power 3, the fade of the radial springs on it (arm_fade: the
//     quintic 7, 1 - s 1, slope 4); and 3 divisions and 1 square root each;
//   radial springs (radial_spring, spring_at), 6 per particle, 106 each: two cross products for
//     n and the two w 27, dot and norm 10, atan2_first_quadrant 27 (reduction 4, z 1, numerator
//     polynomial 8, denominator 9, last terms 5), the angle ratio and its series 6, rest-angle
//     term 1, stiffness per length and gradients 4, angle rate 12, torque 1, elastic term 2, the
//     two forces 12, power 1, switches 2; and 3 divisions and 1 square root each (the fade's own
//     terms, about 20 more, are computed only in a band with an arm inside it, and not counted);
//   per particle besides: the sums into the four neighbours 24 and the power 6
//     (radial_particle), the gather 57 (gravity and drag 9, four tensions 24, own and
//     neighbours' spring forces 24), the damping power's sum 1.
// 80 + 636 + 88 = 804 additions and multiplications, 24 divisions and 8 square roots: 836
// operations, each division and square root counted as one (as LINPACK counts them; they take
// many cycles each, so the peak of additions and multiplications is out of reach). The west and
// north arms' relative velocities are the connectors' own, stored, negated. The same count in
// float32; the float32 kernel's conversions to and from double are not counted.
inline constexpr double kLatticeKernelFlopsPerParticle = 836.0;

// Scratch memory of the structured kernel: padded SoA arrays, allocated by prepare().
class LatticeKernel {
 public:
  // Sizes the scratch for `model` and copies its per-spring parameters, if the model has the
  // lattice layout (ClothModel::layout, recorded by build_lattice; torn, plastic and creased
  // sheets keep it); false (and no scratch) otherwise. `precision`: the arithmetic of the springs
  // (see "Precision" at the top of this file); `both_precisions`: the scratch of the other
  // precision as well, for set_precision().
  bool prepare(const ClothModel& model, Precision precision = Precision::float64, bool both_precisions = false);
  bool active() const { return active_; }
  Precision precision() const { return precision_; }
  // Switches the springs' arithmetic of a prepared kernel (`precision: auto`'s choice, frame by
  // frame: sim/precision_choice.h). The scratch of the new precision is prepare()'s with
  // `both_precisions` (else allocated at the first switch and kept); each switch copies the
  // parameters into the new precision's arrays (O(springs)). The forces in a precision do not
  // depend on the switches before them.
  void set_precision(const ClothModel& model, Precision precision);
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
  // The part of bytes_for() in the arrays of one precision: what set_precision() adds when it
  // first switches to it.
  static std::size_t array_bytes_for(const LatticeCounts& counts, bool parameter_arrays, Precision precision);

 private:
  template <typename Real>
  double evaluate_in(const ClothModel& model, std::span<const Vec3> position, std::span<const Vec3> velocity,
                     std::uint32_t terms, int threads, std::span<Vec3> force);
  // The scratch of precision Real: scratch64_ or scratch32_ (the other stays empty unless
  // set_precision() has switched).
  template <typename Real>
  std::vector<Real>& scratch() {
    if constexpr (std::is_same_v<Real, double>) {
      return scratch64_;
    } else {
      return scratch32_;
    }
  }
  // Reals in the scratch of the current precision.
  std::size_t scratch_size() const { return precision_ == Precision::float64 ? scratch64_.size() : scratch32_.size(); }
  // Resizes the scratch of the current precision, or of `precision`, to `arrays` arrays, new
  // entries zero.
  void resize_scratch(std::size_t arrays);
  void resize_scratch(Precision precision, std::size_t arrays);
  template <typename Real>
  void copy_parameters(const ClothModel& model);
  // Takes the model's parameters: one value per family on a uniform sheet, else every spring's
  // stiffness, damping, rest value and liveness into the padded arrays.
  void refresh(const ClothModel& model);
  // Every connector intact, and every spring of a family with the same stiffness, damping and
  // rest value (and, connectors, original length).
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
    double rest = 0.0;      // rest length (m) or rest angle (rad)
    double original = 0.0;  // connectors: the original length, m, which sets the radial springs' fade
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
  // (lattice_kernel_layout.h): in double, or in float for float32 forces (both once
  // set_precision() has switched).
  std::vector<double> scratch64_;
  std::vector<float> scratch32_;
  std::vector<double> block_power_;
};

}  // namespace clothsim
