// The energy a collision pass changes, summed over what it changed (docs/collisions.md, "Energy
// bookkeeping").
//
// A pass moves some particles and changes some velocities; the sheet's energy changes by the
// kinetic and gravitational energy of those particles and the elastic energy of the springs that
// touch them. Summing only those costs in proportion to what the pass touched, where summing the
// whole sheet twice per step would cost more than the pass. The springs are found through a
// gather table (model/gather_table.h: connector e owns slots 2e, 2e+1; radial r owns
// radial_slot_base() + 3r ..+2), built at the first collect(). Both run over the threads: the
// particles and springs are listed in index order, and summed in fixed blocks added in order
// (core/parallel.h), so the sum is the same for any thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/vec3.h"
#include "forces/forces.h"
#include "model/cloth_model.h"
#include "model/gather_table.h"

namespace clothsim {

class ContactEnergy {
 public:
  // Collects the particles p with changed[p] != 0, in index order, and the springs touching them.
  void collect(const ClothModel& model, std::span<const std::uint8_t> changed, int threads);
  // Kinetic and gravitational energy of the collected particles and elastic energy of the
  // collected springs, at `position` and `velocity` [particle_count()]; the terms switched off in
  // `terms` are left out, as in the simulation's energy balance.
  double energy(const ClothModel& model, std::span<const Vec3> position, std::span<const Vec3> velocity,
                ForceTerms terms, int threads) const;
  std::span<const std::uint32_t> particles() const { return particles_; }
  std::size_t bytes() const;
  // The most bytes() reports on the lattice of `counts`: every particle and spring collected
  // (a sheet lying on the floor) (sim/memory_estimate.h).
  static std::size_t bytes_for(const LatticeCounts& counts) {
    const std::size_t elements = counts.connectors + counts.radials;
    return elements * (sizeof(std::uint8_t) + sizeof(std::uint32_t)) + counts.particles * sizeof(std::uint32_t) +
           GatherTable::bytes_for(counts);
  }

 private:
  std::vector<std::uint8_t> element_mark_;  // [connectors + radials] scratch of collect(), 0 between calls
  std::vector<std::uint32_t> particles_;    // collected particles, ascending
  std::vector<std::uint32_t> elements_;     // connectors e, then radials as connector_count() + r, ascending
  GatherTable gather_;                      // the model's, built at the first collect()
};

}  // namespace clothsim
