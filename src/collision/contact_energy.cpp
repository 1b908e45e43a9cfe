#include "collision/contact_energy.h"

#include <atomic>

#include "core/parallel.h"

namespace clothsim {

void ContactEnergy::collect(const ClothModel& model, std::span<const std::uint8_t> changed, int threads) {
  const std::size_t connectors = model.connector_count();
  if (!gather_.built_for(model)) gather_.build(model);
  element_mark_.resize(connectors + model.radial_count(), 0);
  // Room for every particle and element at once, so that collecting never reallocates between
  // steps and holds what bytes_for() counts, not a vector's growth beyond it.
  particles_.reserve(changed.size());
  elements_.reserve(element_mark_.size());
  parallel_select(changed.size(), threads, [&](std::size_t p) { return changed[p] != 0; }, particles_);
  // Every spring a collected particle belongs to is marked (by any thread that meets it: each
  // writes a 1), then listed in index order; the marks are cleared again for the next call.
  const std::size_t base = model.radial_slot_base();
  parallel_for(particles_.size(), threads, [&](std::size_t k) {
    const std::uint32_t p = particles_[k];
    for (std::uint32_t i = gather_.offset[p]; i < gather_.offset[p + 1]; ++i) {
      const std::size_t slot = gather_.slot[i];
      const std::size_t element = slot < base ? slot / 2 : connectors + (slot - base) / 3;
      std::atomic_ref<std::uint8_t>(element_mark_[element]).store(1, std::memory_order_relaxed);
    }
  });
  parallel_select(element_mark_.size(), threads, [&](std::size_t e) { return element_mark_[e] != 0; }, elements_);
  parallel_for(elements_.size(), threads, [&](std::size_t k) { element_mark_[elements_[k]] = 0; });
}

double ContactEnergy::energy(const ClothModel& model, std::span<const Vec3> position, std::span<const Vec3> velocity,
                             ForceTerms terms, int threads) const {
  const std::array<double, 1> particles = parallel_sum<1>(particles_.size(), threads, [&](std::size_t k) {
    const std::uint32_t p = particles_[k];
    double energy = 0.5 * model.particle_mass[p] * dot(velocity[p], velocity[p]);
    if ((terms & kGravity) != 0) energy -= model.particle_mass[p] * dot(model.environment.gravity, position[p]);
    return std::array<double, 1>{energy};
  });
  const std::size_t connectors = model.connector_count();
  const std::array<double, 1> springs = parallel_sum<1>(elements_.size(), threads, [&](std::size_t k) {
    const std::uint32_t element = elements_[k];
    if (element < connectors) {
      const bool on = (terms & kConnectorSprings) != 0;
      return std::array<double, 1>{on ? connector_spring_energy(model, position, element) : 0.0};
    }
    const std::size_t r = element - connectors;
    const ForceTerms term =
        model.radial_kind[r] == RadialKind::adjacent ? kAdjacentRadialSprings : kOppositeRadialSprings;
    return std::array<double, 1>{(terms & term) != 0 ? radial_spring_energy(model, position, r) : 0.0};
  });
  return particles[0] + springs[0];
}

std::size_t ContactEnergy::bytes() const {
  return element_mark_.capacity() + (particles_.capacity() + elements_.capacity()) * sizeof(std::uint32_t) +
         gather_.bytes();
}

}  // namespace clothsim
