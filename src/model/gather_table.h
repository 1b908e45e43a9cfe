// The force gather table: for each particle, the element slots whose forces act on it.
//
// The general force path (forces/forces.h) writes each element's forces into per-element slots:
// connector e owns slots 2e (its particle a) and 2e + 1 (b); radial spring r owns slots
// ClothModel::radial_slot_base() + 3r (centre), + 1 (b) and + 2 (c). Each particle then sums its
// slots in ascending order, which makes the sum independent of the thread count. The same table
// gives implicit Euler the order in which it assembles a particle's block row, and the collision
// passes the springs touching a particle (collision/contact_energy.h).
//
// Why not in ClothModel: the table is 4 bytes per slot, 22 slots per lattice particle, 92 bytes
// per particle with its offsets, and the lattice kernel (forces/lattice_kernel.h), which serves
// every built lattice, does not read it. Each user builds its own from the model's element arrays
// (docs/performance.md, "Memory"). The table depends only on which particles each element joins,
// which never changes after the model is built (tearing marks elements dead, it does not move
// them), so it is built once.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "model/cloth_model.h"

namespace clothsim {

struct GatherTable {
  // CSR: particle p's slots are slot[offset[p] .. offset[p + 1]), ascending.
  std::vector<std::uint32_t> offset;  // [particle_count() + 1]
  std::vector<std::uint32_t> slot;    // [force_slot_count()]

  void build(const ClothModel& model);
  // True once built for a model of this many particles and slots.
  bool built_for(const ClothModel& model) const {
    return offset.size() == model.particle_count() + 1 && slot.size() == model.force_slot_count();
  }
  std::size_t bytes() const { return (offset.capacity() + slot.capacity()) * sizeof(std::uint32_t); }
  // The bytes bytes() reports once built for the lattice build_lattice() makes with `counts`.
  static std::size_t bytes_for(const LatticeCounts& counts) {
    return (counts.particles + 1 + 2 * counts.connectors + 3 * counts.radials) * sizeof(std::uint32_t);
  }
};

}  // namespace clothsim
