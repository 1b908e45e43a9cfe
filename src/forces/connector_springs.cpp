// Connector (stretch) springs: one pass over the springs, each writing its two force slots.
#include "core/parallel.h"
#include "forces/element.h"
#include "forces/forces.h"

namespace clothsim {

void accumulate_connector_springs(const ClothModel& model, std::span<const Vec3> position,
                                  std::span<const Vec3> velocity, ForceTerms terms, int threads,
                                  ForceBuffers& buffers) {
  const bool elastic = (terms & kConnectorSprings) != 0;
  const bool damped = elastic && (terms & kSpringDamping) != 0;
  Vec3* slot = buffers.slot_force.data();
  double* power = buffers.element_power.data();
  parallel_for(model.connector_count(), threads, [&](std::size_t e) {
    if (!elastic || model.connector_live[e] == 0) {
      slot[2 * e] = slot[2 * e + 1] = Vec3{};
      power[e] = 0.0;
      return;
    }
    const auto [a, b] = model.connector_particles[e];
    const element::ConnectorForce f =
        element::connector_force(position[a], position[b], velocity[a], velocity[b], model.connector_rest_length[e],
                                 model.connector_stiffness[e], damped ? model.connector_damping[e] : 0.0);
    slot[2 * e] = f.force_on_a;
    slot[2 * e + 1] = -f.force_on_a;
    power[e] = f.damping_power;
  });
}

double connector_spring_energy(const ClothModel& model, std::span<const Vec3> position, std::size_t e) {
  if (model.connector_live[e] == 0) return 0.0;
  const auto [a, b] = model.connector_particles[e];
  return element::connector_energy(position[a], position[b], model.connector_rest_length[e],
                                   model.connector_stiffness[e]);
}

double connector_energy(const ClothModel& model, std::span<const Vec3> position, int threads) {
  return parallel_sum<1>(model.connector_count(), threads,
                         [&](std::size_t e) { return std::array{connector_spring_energy(model, position, e)}; })[0];
}

}  // namespace clothsim
