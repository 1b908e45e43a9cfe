// The force function: positions and velocities -> force on every particle.
//
// Each term has its own file with one accumulate entry and a matching energy function:
//   connector_springs.cpp  connector (stretch) springs
//   radial_springs.cpp     radial (angular) springs, adjacent and opposite
//   external_forces.cpp    gravity and linear air drag
// Spring terms write per-element forces into slots (one per element end), and gather_forces()
// sums each particle's slots in a fixed order and adds the external forces. No two threads ever
// add into the same value, so the result is bit-for-bit the same for any thread count; this costs
// one extra pass over memory compared with scattered atomic adds, and keeps runs reproducible.
// The per-element math itself is in element.h.
//
// A sheet with the lattice layout (what build_lattice makes, torn, plastic or creased) takes a
// second, vectorised path through the same physics: lattice_kernel.h. ForceBuffers::resize()
// chooses the path once per model; evaluate_forces() then follows it, and both read the model's
// current per-spring values (the kernel copies them again when the model's revision moves). Both give the same forces
// up to rounding (tests/forces/test_lattice_kernel.cpp), and each is bit-for-bit independent of the thread count.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/vec3.h"
#include "forces/lattice_kernel.h"
#include "model/cloth_model.h"
#include "model/gather_table.h"

namespace clothsim {

// Bitmask of force terms; tests switch terms off to isolate physics.
using ForceTerms = std::uint32_t;
inline constexpr ForceTerms kGravity = 1u << 0;
inline constexpr ForceTerms kConnectorSprings = 1u << 1;
inline constexpr ForceTerms kAdjacentRadialSprings = 1u << 2;
inline constexpr ForceTerms kOppositeRadialSprings = 1u << 3;
inline constexpr ForceTerms kAirDrag = 1u << 4;
inline constexpr ForceTerms kSpringDamping = 1u << 5;  // damping of connector and radial springs
inline constexpr ForceTerms kAllForceTerms = (1u << 6) - 1;

// Which implementation of the force function evaluate_forces() runs.
enum class ForceKernel : std::uint8_t {
  automatic,  // the lattice kernel when the model has the lattice layout, else the general one
  general,    // element lists and per-element slots: any sheet
  lattice,    // the structured kernel; resize() fails an assertion if the model is not a lattice
};

// Scratch memory for one force evaluation, sized by resize() for a model. Changes through
// model/model_edits.h (tearing, plasticity, live edits) need no resize(): elements keep their
// index, and the kernel follows the model's revision. Only the chosen path's scratch is held: the
// general path's per-slot arrays and gather table stay empty while the lattice kernel is in use
// (they would be 684 bytes per particle of a lattice, more than the kernel's own scratch).
struct ForceBuffers {
  ForceKernel kernel = ForceKernel::automatic;  // set before resize()
  // Set before resize(): float32 runs the lattice kernel's springs in float (lattice_kernel.h,
  // "Precision"); resize() fails an assertion if the model is not a lattice then.
  Precision precision = Precision::float64;
  // Set before resize(): the lattice kernel's scratch in both precisions, for set_precision().
  bool both_precisions = false;
  std::vector<Vec3> slot_force;       // general path: [model.force_slot_count()], N
  std::vector<double> element_power;  // general path: [connectors + radials], damping power per element, W
  std::vector<double> block_power;    // general path: partial sums over fixed blocks of element_power
  GatherTable gather;                 // general path: each particle's slots
  LatticeKernel lattice;              // scratch of the structured kernel, when it is in use
  void resize(const ClothModel& model);
  bool uses_lattice_kernel() const { return lattice.active(); }
  // Switches the springs' arithmetic after resize(), on the lattice kernel only
  // (LatticeKernel::set_precision): `precision: auto`'s choice (sim/precision_choice.h).
  void set_precision(const ClothModel& model, Precision next);
  // Bytes of scratch memory held.
  std::size_t bytes() const;
  // The bytes bytes() reports after resize() for the lattice build_lattice() makes with `counts`,
  // with `kernel`, in `precision`; `parameter_arrays`: whether the lattice kernel keeps them
  // (LatticeKernel::bytes_for) (the memory estimate, sim/memory_estimate.h).
  static std::size_t bytes_for(const LatticeCounts& counts, ForceKernel kernel, bool parameter_arrays,
                               Precision precision = Precision::float64);
};

// Powers of the dissipative forces at the evaluated state (W, never positive).
struct ForcePowers {
  double damping = 0.0;  // spring damping
  double drag = 0.0;     // air drag
};

// Computes the total force on every particle (anchored ones included) into `force`
// [particle_count()]. `threads` >= 1.
ForcePowers evaluate_forces(const ClothModel& model, std::span<const Vec3> position, std::span<const Vec3> velocity,
                            ForceTerms terms, int threads, ForceBuffers& buffers, std::span<Vec3> force);

// Per-term entries, used by evaluate_forces() and by tests.
void accumulate_connector_springs(const ClothModel& model, std::span<const Vec3> position,
                                  std::span<const Vec3> velocity, ForceTerms terms, int threads, ForceBuffers& buffers);
void accumulate_radial_springs(const ClothModel& model, std::span<const Vec3> position, std::span<const Vec3> velocity,
                               ForceTerms terms, int threads, ForceBuffers& buffers);
void gather_forces(const ClothModel& model, std::span<const Vec3> velocity, ForceTerms terms, int threads,
                   const ForceBuffers& buffers, std::span<Vec3> force);

// Energies of a configuration, J.
struct EnergyReport {
  double kinetic = 0.0;
  double gravitational = 0.0;  // -m g . x, zero at y = 0 for the default gravity
  double connector = 0.0;
  double radial_adjacent = 0.0;
  double radial_opposite = 0.0;
  double total() const { return kinetic + gravitational + connector + radial_adjacent + radial_opposite; }

  // The stored terms, in order (core/record_fields.h); total() is reported beside them where a
  // record of energies is written (EnergyBalance).
  template <typename Self, typename Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit("kinetic", self.kinetic);
    visit("gravitational", self.gravitational);
    visit("connector", self.connector);
    visit("radial_adjacent", self.radial_adjacent);
    visit("radial_opposite", self.radial_opposite);
  }
};

// The sums below are parallel over `threads` in fixed blocks (core/parallel.h, parallel_sum): the
// same bits for any thread count. A frame's energies on a large sheet (a 1024 x 1024 lattice's 6
// million radial springs, each an arctangent) took 60 ms on one thread, more than the Vulkan
// backend's steps of the frame.
double connector_energy(const ClothModel& model, std::span<const Vec3> position, int threads = 1);
// Elastic energy of one connector or radial spring (0 once broken), J.
double connector_spring_energy(const ClothModel& model, std::span<const Vec3> position, std::size_t connector);
double radial_spring_energy(const ClothModel& model, std::span<const Vec3> position, std::size_t radial);
// The fade lengths of radial spring `radial`'s two arms (centre-b, centre-c): element_math.inc's
// kRadialFadeFraction times each arm connector's original length, m. Every path that evaluates a
// radial spring of the model takes them from here.
std::array<double, 2> radial_fade_lengths(const ClothModel& model, std::size_t radial);
// Adds the radial springs' energy into report.radial_adjacent and report.radial_opposite.
void add_radial_energy(const ClothModel& model, std::span<const Vec3> position, EnergyReport& report, int threads = 1);
double kinetic_energy(const ClothModel& model, std::span<const Vec3> velocity, int threads = 1);
double gravitational_energy(const ClothModel& model, std::span<const Vec3> position, int threads = 1);

// All energies of `state`, terms switched off in `terms` left at zero.
EnergyReport compute_energy(const ClothModel& model, const ClothState& state, ForceTerms terms = kAllForceTerms,
                            int threads = 1);

// Sums `values` over fixed blocks in index order, in double: the same result for any thread
// count. `block_sums` needs deterministic_sum_blocks(values.size()) entries.
double deterministic_sum(std::span<const double> values, int threads, std::vector<double>& block_sums);
double deterministic_sum(std::span<const float> values, int threads, std::vector<double>& block_sums);
std::size_t deterministic_sum_blocks(std::size_t count);

}  // namespace clothsim
