// Gravity and linear air drag, and the energies that go with particles alone.
#include "forces/forces.h"

namespace clothsim {

double kinetic_energy(const ClothModel& model, std::span<const Vec3> velocity) {
  double energy = 0.0;
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    energy += 0.5 * model.particle_mass[p] * squared_norm(velocity[p]);
  }
  return energy;
}

double gravitational_energy(const ClothModel& model, std::span<const Vec3> position) {
  double energy = 0.0;
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    energy -= model.particle_mass[p] * dot(model.environment.gravity, position[p]);
  }
  return energy;
}

}  // namespace clothsim
