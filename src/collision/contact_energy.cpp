#include "collision/contact_energy.h"

namespace clothsim {

void ContactEnergy::collect(const ClothModel& model, std::span<const std::uint8_t> changed) {
  const std::size_t connectors = model.connector_count();
  if (!gather_.built_for(model)) gather_.build(model);
  element_mark_.resize(connectors + model.radial_count(), 0);
  // Room for every particle and element at once, so that collecting never reallocates between
  // steps and holds what bytes_for() counts, not a vector's growth beyond it.
  particles_.reserve(changed.size());
  elements_.reserve(element_mark_.size());
  for (std::uint32_t element : elements_) element_mark_[element] = 0;
  particles_.clear();
  elements_.clear();
  const std::size_t base = model.radial_slot_base();
  for (std::size_t p = 0; p < changed.size(); ++p) {
    if (changed[p] == 0) continue;
    particles_.push_back(static_cast<std::uint32_t>(p));
    for (std::uint32_t i = gather_.offset[p]; i < gather_.offset[p + 1]; ++i) {
      const std::size_t slot = gather_.slot[i];
      const std::size_t element = slot < base ? slot / 2 : connectors + (slot - base) / 3;
      if (element_mark_[element] != 0) continue;
      element_mark_[element] = 1;
      elements_.push_back(static_cast<std::uint32_t>(element));
    }
  }
}

double ContactEnergy::energy(const ClothModel& model, std::span<const Vec3> position, std::span<const Vec3> velocity,
                             ForceTerms terms) const {
  double energy = 0.0;
  for (std::uint32_t p : particles_) {
    energy += 0.5 * model.particle_mass[p] * dot(velocity[p], velocity[p]);
    if ((terms & kGravity) != 0) energy -= model.particle_mass[p] * dot(model.environment.gravity, position[p]);
  }
  const std::size_t connectors = model.connector_count();
  for (std::uint32_t element : elements_) {
    if (element < connectors) {
      if ((terms & kConnectorSprings) != 0) energy += connector_spring_energy(model, position, element);
    } else {
      const std::size_t r = element - connectors;
      const ForceTerms term =
          model.radial_kind[r] == RadialKind::adjacent ? kAdjacentRadialSprings : kOppositeRadialSprings;
      if ((terms & term) != 0) energy += radial_spring_energy(model, position, r);
    }
  }
  return energy;
}

std::size_t ContactEnergy::bytes() const {
  return element_mark_.capacity() + (particles_.capacity() + elements_.capacity()) * sizeof(std::uint32_t) +
         gather_.bytes();
}

}  // namespace clothsim
