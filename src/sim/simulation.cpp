#include "sim/simulation.h"

#include <cmath>
#include <cstdio>

#include "core/assert.h"
#include "core/parallel.h"
#include "core/timer.h"

namespace clothsim {
namespace {

std::string format_number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

std::string format_vector(const Vec3& v) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.6g, %.6g, %.6g)", v.x, v.y, v.z);
  return buffer;
}

}  // namespace

Simulation::Simulation(ClothModel model, ClothState initial, const SimulationSettings& settings)
    : model_(std::make_unique<ClothModel>(std::move(model))), state_(std::move(initial)), settings_(settings) {
  CLOTHSIM_ASSERT(state_.position.size() == model_->particle_count(), "state matches the model");
  CLOTHSIM_ASSERT(state_.velocity.size() == model_->particle_count(), "state matches the model");
  threads_ = resolve_thread_count(settings.threads, model_->particle_count());
  integrator_ = make_integrator(*model_, settings.integrator, ForceOptions{settings.terms, threads_, settings.kernel});
  initial_energy_ = energy().total() - (state_.damping_work + state_.drag_work + state_.anchor_work);
  check_state();
}

bool Simulation::advance_to(double time) {
  if (failure_) return false;
  CLOTHSIM_ASSERT(time >= state_.time, "advance_to() cannot go back in time");
  while (state_.time < time) {
    {
      Stopwatch watch;
      const double force_before = integrator_->force_seconds();
      const StepOutcome outcome = integrator_->step(state_, time);
      const double force = integrator_->force_seconds() - force_before;
      profile_.forces += force;
      profile_.integration += watch.seconds() - force;

      if (outcome.status == StepStatus::step_underflow) {
        const std::string where = model_->describe_particle(outcome.particle);
        fail(where, std::string(outcome.non_finite_error ? "forces became non-finite" : "step size underflow") +
                        ": " + std::string(to_string(settings_.integrator.kind)) + " needed a step of " +
                        format_number(outcome.step) + " s, below min_step = " +
                        format_number(settings_.integrator.min_step) + " s; the largest error is at " + where +
                        ". The state is blowing up, or the problem is too stiff for this tolerance.");
        return false;
      }
      if (outcome.status == StepStatus::non_finite) {
        const std::string where = model_->describe_particle(outcome.particle);
        fail(where, "the state became non-finite at " + where + " during a step of " + format_number(outcome.step) +
                        " s; the time step is too large for this material (try a smaller --time-step or rkf45).");
        return false;
      }
    }
    // Discrete events (tearing, plasticity, creasing) will run here, between accepted steps.
    {
      ScopedTimer timer(profile_.checks);
      check_state();
    }
    if (failure_) return false;
  }
  return true;
}

void Simulation::check_state() {
  const ClothModel& model = *model_;
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    if (!is_finite(state_.position[p]) || !is_finite(state_.velocity[p])) {
      const std::string where = model.describe_particle(p);
      fail(where, "non-finite state at " + where + ": position " + format_vector(state_.position[p]) +
                      ", velocity " + format_vector(state_.velocity[p]));
      return;
    }
  }
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    const auto [a, b] = model.connector_particles[e];
    const double stretch = norm(state_.position[b] - state_.position[a]) / model.connector_rest_length[e];
    if (stretch > settings_.explosion_stretch) {
      const std::string where = "connector " + std::to_string(e) + " between " + model.describe_particle(a) +
                                " and " + model.describe_particle(b);
      fail(where, "the simulation exploded: " + where + " is " + format_number(stretch) +
                      " times its rest length (limit " + format_number(settings_.explosion_stretch) + ")");
      return;
    }
  }
}

void Simulation::fail(std::string element, std::string message) {
  Diagnosis diagnosis;
  diagnosis.time = state_.time;
  diagnosis.step = integrator_ ? integrator_->stats().accepted_steps : 0;
  diagnosis.element = std::move(element);
  diagnosis.message = "at t = " + format_number(diagnosis.time) + " s (step " + std::to_string(diagnosis.step) +
                      "): " + message;
  failure_ = std::move(diagnosis);
}

namespace {

template <typename T>
std::size_t vector_bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

std::size_t model_bytes(const ClothModel& m) {
  return vector_bytes(m.particle_mass) + vector_bytes(m.particle_inverse_mass) + vector_bytes(m.particle_anchor) +
         vector_bytes(m.particle_rest_position) + vector_bytes(m.connector_particles) +
         vector_bytes(m.connector_rest_length) + vector_bytes(m.connector_stiffness) +
         vector_bytes(m.connector_damping) + vector_bytes(m.radial_particles) + vector_bytes(m.radial_connectors) +
         vector_bytes(m.radial_kind) + vector_bytes(m.radial_rest_angle) + vector_bytes(m.radial_stiffness) +
         vector_bytes(m.radial_damping) + vector_bytes(m.anchors) + vector_bytes(m.gather_offset) +
         vector_bytes(m.gather_slot);
}

}  // namespace

std::size_t Simulation::memory_bytes() const {
  return model_bytes(*model_) + vector_bytes(state_.position) + vector_bytes(state_.velocity) +
         integrator_->workspace_bytes();
}

EnergyReport Simulation::energy() const { return compute_energy(*model_, state_, settings_.terms); }

EnergyBalance Simulation::energy_balance() const {
  EnergyBalance balance;
  balance.energy = energy();
  balance.initial_total = initial_energy_;
  balance.damping_work = state_.damping_work;
  balance.drag_work = state_.drag_work;
  balance.anchor_work = state_.anchor_work;
  return balance;
}

}  // namespace clothsim
