// Gravity and linear air drag, and the energies that go with particles alone.
#include "core/parallel.h"
#include "forces/forces.h"

namespace clothsim {

double kinetic_energy(const ClothModel& model, std::span<const Vec3> velocity, int threads) {
  return parallel_sum<1>(model.particle_count(), threads, [&](std::size_t p) {
    return std::array{0.5 * model.particle_mass[p] * squared_norm(velocity[p])};
  })[0];
}

double gravitational_energy(const ClothModel& model, std::span<const Vec3> position, int threads) {
  return parallel_sum<1>(model.particle_count(), threads, [&](std::size_t p) {
    return std::array{-model.particle_mass[p] * dot(model.environment.gravity, position[p])};
  })[0];
}

}  // namespace clothsim
