// Simulation's live edits (sim/simulation.h, "Live editing"): parameters, limits, cuts, the
// integrator, runtime anchors and obstacles, each between advance_to() calls and each through
// model/model_edits.h, booking the energy it adds or removes.
#include <memory>
#include <utility>

#include "core/assert.h"
#include "model/model_edits.h"
#include "sim/anchor_events.h"
#include "sim/simulation.h"

namespace clothsim {

void Simulation::set_spring_parameters(SpringFamily family, const SpringParameters& parameters) {
  checked_energy_.reset();
  const double before = energy().total();
  set_spring_family(*model_, family, parameters);
  edit_work_ += energy().total() - before;
}

void Simulation::set_environment(const Environment& environment) {
  checked_energy_.reset();
  const double before = energy().total();
  clothsim::set_environment(*model_, environment);
  edit_work_ += energy().total() - before;
}

void Simulation::require_backend_runs(const BackendFeatures& features) const {
  const std::string unsupported = unsupported_by_backend(features, settings_.backend);
  if (!unsupported.empty()) throw BackendError(backend_refusal(unsupported, settings_.backend));
}

void Simulation::set_spring_limits(const SpringLimits& limits) {
  checked_energy_.reset();
  BackendFeatures features = features_of(*model_, settings_.integrator);
  features.limits = limits;
  require_backend_runs(features);
  apply_spring_limits(*model_, limits);
}

std::size_t Simulation::cut_connectors(std::span<const std::uint32_t> connectors) {
  checked_energy_.reset();
  std::size_t cut = 0;
  for (std::uint32_t e : connectors) cut += tear_connector(*model_, state_, e) ? 1 : 0;
  return cut;
}

void Simulation::set_particle_mass(double mass) {
  checked_energy_.reset();
  const double before = energy().total();
  clothsim::set_particle_mass(*model_, mass);
  edit_work_ += energy().total() - before;
}

void Simulation::set_integrator(const IntegratorSettings& settings) {
  checked_energy_.reset();
  const IntegratorSettings before = settings_.integrator;
  settings_.integrator = settings;
  try {
    restart_integrator();
  } catch (const BackendError&) {
    settings_.integrator = before;
    throw;
  }
}

void Simulation::restart_integrator() {
  std::unique_ptr<Integrator> next = new_integrator();
  retired_stats_ = integrator_stats();
  retired_profile_ += integrator_->profile();
  integrator_ = std::move(next);
}

void Simulation::pin_particle(std::uint32_t particle) {
  checked_energy_.reset();
  CLOTHSIM_ASSERT(particle < model_->particle_count(), "pinned particle is in the lattice");
  hold_on_path(*model_, state_, particle, AnchorPath::fixed_at(state_.position[particle]));
}

void Simulation::drive_particle(std::uint32_t particle, const Vec3& target, double arrival_time) {
  checked_energy_.reset();
  CLOTHSIM_ASSERT(particle < model_->particle_count(), "driven particle is in the lattice");
  CLOTHSIM_ASSERT(arrival_time > state_.time, "a driven particle arrives after the current time");
  AnchorPath path;
  path.kind = AnchorPathKind::driven;
  path.origin = state_.position[particle];
  path.start_time = state_.time;
  path.end_time = arrival_time;
  path.velocity = (target - path.origin) / (arrival_time - state_.time);
  hold_on_path(*model_, state_, particle, path);
}

void Simulation::place_particle(std::uint32_t particle, const Vec3& position) {
  checked_energy_.reset();
  CLOTHSIM_ASSERT(particle < model_->particle_count() && model_->is_anchored(particle),
                  "only an anchored particle is placed");
  const double before = energy().total();
  AnchorPath path;
  path.kind = AnchorPathKind::driven;
  path.origin = position;
  path.start_time = state_.time;
  set_anchor(*model_, particle, path);
  state_.position[particle] = position;
  state_.velocity[particle] = Vec3{};
  edit_work_ += energy().total() - before;
}

bool Simulation::release_particle(std::uint32_t particle) {
  checked_energy_.reset();
  CLOTHSIM_ASSERT(particle < model_->particle_count(), "released particle is in the lattice");
  return remove_anchor(*model_, particle);
}

void Simulation::set_self_collision(bool on) {
  checked_energy_.reset();
  BackendFeatures features = features_of(*model_, settings_.integrator);
  features.self_collision = on;
  require_backend_runs(features);
  clothsim::set_self_collision(*model_, on);
}

std::size_t Simulation::add_collider(const Collider& collider) {
  checked_energy_.reset();
  BackendFeatures features = features_of(*model_, settings_.integrator);
  features.colliders = true;
  require_backend_runs(features);
  return clothsim::add_collider(*model_, collider);
}

void Simulation::drive_collider(std::size_t collider, const Vec3& displacement, double arrival_time) {
  checked_energy_.reset();
  clothsim::drive_collider(*model_, collider, displacement, state_.time, arrival_time);
}

void Simulation::place_collider(std::size_t collider, const Vec3& displacement) {
  checked_energy_.reset();
  clothsim::place_collider(*model_, collider, displacement, state_.time);
}

}  // namespace clothsim
