// Radial (angular) springs: one pass over the springs, each writing its three force slots
// (centre, b, c). The centre's force is minus the sum of the other two, so the element exerts no
// net force; it also exerts no net torque about the centre because both forces lie in the plane
// of the connectors and are perpendicular to them (docs/model.md).
#include "core/parallel.h"
#include "forces/element.h"
#include "forces/forces.h"

namespace clothsim {

void accumulate_radial_springs(const ClothModel& model, std::span<const Vec3> position, std::span<const Vec3> velocity,
                               ForceTerms terms, int threads, ForceBuffers& buffers) {
  const bool damped = (terms & kSpringDamping) != 0;
  Vec3* slot = buffers.slot_force.data() + model.radial_slot_base();
  double* power = buffers.element_power.data() + model.connector_count();
  parallel_for(model.radial_count(), threads, [&](std::size_t r) {
    const ForceTerms term =
        model.radial_kind[r] == RadialKind::adjacent ? kAdjacentRadialSprings : kOppositeRadialSprings;
    if ((terms & term) == 0 || model.radial_live[r] == 0) {
      slot[3 * r] = slot[3 * r + 1] = slot[3 * r + 2] = Vec3{};
      power[r] = 0.0;
      return;
    }
    const auto [centre, b, c] = model.radial_particles[r];
    const std::array<double, 2> fade = radial_fade_lengths(model, r);
    const element::RadialForce f =
        element::radial_force(position[centre], position[b], position[c], velocity[centre], velocity[b], velocity[c],
                              model.radial_rest_angle[r], model.radial_stiffness[r],
                              damped ? model.radial_damping[r] : 0.0, fade[0], fade[1]);
    slot[3 * r] = -(f.force_on_b + f.force_on_c);
    slot[3 * r + 1] = f.force_on_b;
    slot[3 * r + 2] = f.force_on_c;
    power[r] = f.damping_power;
  });
}

double radial_spring_energy(const ClothModel& model, std::span<const Vec3> position, std::size_t r) {
  if (model.radial_live[r] == 0) return 0.0;
  const auto [centre, b, c] = model.radial_particles[r];
  const std::array<double, 2> fade = radial_fade_lengths(model, r);
  return element::radial_energy(position[centre], position[b], position[c], model.radial_rest_angle[r],
                                model.radial_stiffness[r], fade[0], fade[1]);
}

std::array<double, 2> radial_fade_lengths(const ClothModel& model, std::size_t r) {
  const auto [first, second] = model.radial_connectors[r];
  return {element::kRadialFadeFraction * model.connector_original_length[first],
          element::kRadialFadeFraction * model.connector_original_length[second]};
}

void add_radial_energy(const ClothModel& model, std::span<const Vec3> position, EnergyReport& report, int threads) {
  const std::array<double, 2> sums = parallel_sum<2>(model.radial_count(), threads, [&](std::size_t r) {
    const double energy = radial_spring_energy(model, position, r);
    return model.radial_kind[r] == RadialKind::adjacent ? std::array{energy, 0.0} : std::array{0.0, energy};
  });
  report.radial_adjacent += sums[0];
  report.radial_opposite += sums[1];
}

}  // namespace clothsim
