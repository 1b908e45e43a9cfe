#include "model/gather_table.h"

#include "core/assert.h"

namespace clothsim {

void GatherTable::build(const ClothModel& model) {
  const std::size_t n = model.particle_count();
  const auto slot_owner = [&](std::size_t s) -> std::uint32_t {
    if (s < model.radial_slot_base()) return model.connector_particles[s / 2][s % 2];
    const std::size_t local = s - model.radial_slot_base();
    return model.radial_particles[local / 3][local % 3];
  };
  const std::size_t slots = model.force_slot_count();
  offset.assign(n + 1, 0);
  for (std::size_t s = 0; s < slots; ++s) ++offset[slot_owner(s) + 1];
  for (std::size_t p = 0; p < n; ++p) offset[p + 1] += offset[p];
  slot.assign(slots, 0);
  std::vector<std::uint32_t> cursor(offset.begin(), offset.end() - 1);
  // Slots are visited in ascending order, so each particle's list is sorted: a fixed order of
  // summation that does not depend on how the work is split between threads.
  for (std::size_t s = 0; s < slots; ++s) slot[cursor[slot_owner(s)]++] = static_cast<std::uint32_t>(s);
  // What the forces' bit-identity across thread counts rests on, checked in validating builds
  // (-DCLOTHSIM_VALIDATE=ON: the debug and sanitize presets): every slot listed under its own
  // particle, in ascending order.
  CLOTHSIM_VALIDATE_ONLY(for (std::size_t p = 0; p < n; ++p) {
    for (std::uint32_t i = offset[p]; i < offset[p + 1]; ++i) {
      CLOTHSIM_ASSERT(slot_owner(slot[i]) == p, "a gather slot is listed under the particle it acts on");
      CLOTHSIM_ASSERT(i == offset[p] || slot[i - 1] < slot[i], "a particle's gather slots ascend");
    }
  })
}

}  // namespace clothsim
