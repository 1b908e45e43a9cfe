#include "sim/simulation.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/assert.h"
#include "core/diagnostic_text.h"
#include "core/parallel.h"
#include "core/step_profile.h"
#include "sim/anchor_events.h"
#include "sim/step_diagnosis.h"

namespace clothsim {

Simulation::Simulation(ClothModel model, ClothState initial, const SimulationSettings& settings)
    : model_(std::make_unique<ClothModel>(std::move(model))), state_(std::move(initial)), settings_(settings) {
  CLOTHSIM_ASSERT(state_.position.size() == model_->particle_count(), "state matches the model");
  CLOTHSIM_ASSERT(state_.velocity.size() == model_->particle_count(), "state matches the model");
  threads_ = resolve_thread_count(settings.threads, model_->particle_count());
  integrator_ = new_integrator();
  initial_report_ = energy();
  initial_energy_ = initial_report_.total() - (state_.damping_work + state_.drag_work + state_.anchor_work +
                                               state_.plastic_work + state_.fracture_work + state_.contact_work);
  // The least energy scale: the sheet's weight times its size (or, without gravity, its energy).
  // (A picojoule at least, so that a sheet with nothing to move does not fail on rounding.)
  Vec3 low = state_.position.empty() ? Vec3{} : state_.position[0];
  Vec3 high = low;
  double mass = 0.0;
  for (std::size_t p = 0; p < model_->particle_count(); ++p) {
    const Vec3& x = state_.position[p];
    low = {std::min(low.x, x.x), std::min(low.y, x.y), std::min(low.z, x.z)};
    high = {std::max(high.x, x.x), std::max(high.y, x.y), std::max(high.z, x.z)};
    mass += model_->particle_mass[p];
  }
  energy_scale_ = std::max(1e-12, mass * norm(model_->environment.gravity) * norm(high - low));
  check_state();
}

std::unique_ptr<Integrator> Simulation::new_integrator() {
  std::unique_ptr<Integrator> integrator = make_backend_integrator(
      *model_, settings_.integrator, ForceOptions{settings_.terms, threads_, settings_.kernel}, settings_.backend);
  integrator->set_surface_contacts(&collision_stage_->surface_contacts());
  const bool lattice = lattice_forces(*model_, settings_.kernel);
  precision_choice_.configure(settings_.backend.chooses_by_frame(settings_.integrator, lattice),
                              settings_.integrator.absolute_tolerance);
  return integrator;
}

bool Simulation::advance_to(double time) {
  if (failure_) return false;
  checked_energy_.reset();
  CLOTHSIM_ASSERT(time >= state_.time, "advance_to() cannot go back in time");
  precision_choice_.begin_advance();
  while (state_.time < time) {
    // The collision stage's swept tests start from the positions before the step, and an
    // approaching impact limits the step (collision/obstacle_contacts.h); an integrator that
    // resolves the obstacles itself limits its own steps.
    const double step_end = std::min(time, begin_collisions());
    if (!integrate(step_end)) return false;
    collide();
    move_anchors();
    apply_events();
    if (!check()) return false;
  }
  return check_energy_balance();
}

bool Simulation::check_energy_balance() {
  StageTimer timer(profile_, StepStage::checks);
  // The energy scale: every energy the run has had to move, besides the error itself: the kinetic
  // and elastic energy it started with, the most gravitational energy it released or gained, and
  // the work of anchors, obstacles, edits and sheet changes, its changes between checks summed in
  // magnitude. A blown-up run's error grows past it by orders of magnitude (rk4 at 23 times its
  // stable step: 7e9 J against 1.7e4 J); implicit Euler's own dissipation makes the error negative,
  // and its first-order work integrals reach 1.3 times the scale in `paper-crease`
  // (docs/cli.md, "The blow-up check").
  const EnergyBalance balance = energy_balance();
  const EnergyReport& e = balance.energy;
  const std::array<double, 5> works{balance.anchor_work, balance.contact_work, balance.edit_work, balance.plastic_work,
                                    balance.fracture_work};
  for (std::size_t k = 0; k < works.size(); ++k) {
    moved_work_ += std::abs(works[k] - last_works_[k]);  // anchors shaking back and forth move energy both ways
    last_works_[k] = works[k];
  }
  released_ = std::max(released_, std::abs(e.gravitational - initial_report_.gravitational));
  energy_scale_ =
      std::max(energy_scale_, initial_report_.total() - initial_report_.gravitational + released_ + moved_work_);
  const double limit = settings_.integrator.energy_error_limit;
  const double error = balance.error();
  if (!(error > limit * energy_scale_)) {
    checked_energy_ = e;  // what energy() gives until the state or the model changes
    return true;
  }
  // The worst element: the fastest particle.
  std::size_t fastest = 0;
  for (std::size_t p = 1; p < state_.velocity.size(); ++p) {
    if (squared_norm(state_.velocity[p]) > squared_norm(state_.velocity[fastest])) fastest = p;
  }
  const std::string where = model_->describe_particle(fastest);
  fail(where, "the integration has blown up: the energy balance is off by " + diagnostic_number(error) +
                  " J, more than integrator.energy_error_limit = " + diagnostic_number(limit) +
                  " times the run's energy scale of " + diagnostic_number(energy_scale_) +
                  " J; the fastest particle is " + where + " at " + diagnostic_number(norm(state_.velocity[fastest])) +
                  " m/s. " + blow_up_advice(settings_.integrator.kind));
  return false;
}

std::string blow_up_advice(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::implicit_euler:
      // Stable, but its one Newton step a step can put energy in where the sheet turns fast
      // about a pin (docs/cli.md, "The blow-up check").
      return "Implicit Euler takes one Newton step a step, whose linearisation can create energy where the sheet "
             "turns fast about an anchor: try a smaller --time-step (its default is the frame step), or "
             "--integrator rkf45 (adaptive).";
    case IntegratorKind::rkf45:
    case IntegratorKind::imex:
      return "Try tighter tolerances (--rtol, --atol), or --integrator implicit-euler (stable for any step).";
    case IntegratorKind::rk4:
    case IntegratorKind::symplectic_euler: break;
  }
  return "Try a smaller --time-step, or --integrator rkf45 (adaptive) or implicit-euler (stable for any step).";
}

double Simulation::begin_collisions() {
  StageTimer timer(profile_, StepStage::collisions);
  const CollisionPasses passes = integrator_->runs_self_contacts()       ? CollisionPasses::none
                                 : integrator_->runs_obstacle_contacts() ? CollisionPasses::self_only
                                                                         : CollisionPasses::all;
  return collision_stage_->begin_step(*model_, state_, threads_, passes);
}

bool Simulation::host_works_between_steps() const {
  const bool events = model_->limits.changes_sheet() && !integrator_->runs_spring_events();
  const bool obstacles = !model_->colliders.empty() && !integrator_->runs_obstacle_contacts();
  const bool self = model_->collision.self && !integrator_->runs_self_contacts();
  return events || obstacles || self;
}

bool Simulation::integrate(double time) {
  // The whole of the integrator's work; profile() takes its forces out of it.
  StageTimer timer(profile_, StepStage::integration);
  precision_choice_.before_step(*integrator_, state_);
  // Anchor events (a driven anchor arriving, an anchor letting go) are never crossed by a step.
  // One step on the CPU; on a device, every step up to the limit, unless the host has work between
  // steps that the device does not do (host_works_between_steps).
  double end = std::min(time, next_anchor_event(*model_, state_.time));
  // An integrator that resolves the obstacles itself takes their paths one segment at a time.
  if (integrator_->runs_obstacle_contacts()) end = std::min(end, next_collider_event(*model_, state_.time));
  const StepOutcome outcome =
      host_works_between_steps() ? integrator_->step(state_, end) : integrator_->advance(state_, end);

  if (outcome.status == StepStatus::step_underflow) {
    const std::string where = model_->describe_particle(outcome.particle);
    // What the largest error comes from: the spring at that particle nearest a kink of its angle,
    // or furthest from rest (sim/step_diagnosis.h).
    const StepLimit limit = find_step_limit(*model_, state_.position, outcome.particle);
    std::string cause = describe_step_limit(*model_, limit, state_.position);
    if (!cause.empty()) cause[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(cause[0])));
    const std::string advice = limit.collapsed ? " Nothing in the model keeps a particle from passing through its "
                                                 "neighbour but self-collision (collision.self)."
                               : limit.at_kink
                                   ? " The step control cannot follow a force that turns abruptly; a looser "
                                     "tolerance or implicit-euler steps past it."
                                   : " The state is blowing up, or the problem is too stiff for this tolerance "
                                     "(try a looser rtol/atol, or implicit-euler).";
    fail(where, std::string(outcome.non_finite_error ? "forces became non-finite" : "step size underflow") + ": " +
                    std::string(to_string(settings_.integrator.kind)) + " needed a step of " +
                    diagnostic_number(outcome.step) +
                    " s, below min_step = " + diagnostic_number(settings_.integrator.min_step) +
                    " s; the largest error is at " + where + "." + (cause.empty() ? "" : " " + cause + ".") + advice);
    return false;
  }
  if (outcome.status == StepStatus::non_finite) {
    const std::string where = model_->describe_particle(outcome.particle);
    fail(where, "the state became non-finite at " + where + " during a step of " + diagnostic_number(outcome.step) +
                    " s; the time step is too large for this material (try a smaller --time-step or rkf45).");
    return false;
  }
  return true;
}

void Simulation::collide() {
  ContactStatistics& statistics = contact_statistics_;
  StageTimer timer(profile_, StepStage::collisions);
  // The obstacles: the integrator's advance resolved them (a device), or the stage's pass; then the
  // stage's self pass, which has the last word.
  const CollisionCounts counts = collision_stage_->apply(*model_, state_, settings_.terms, threads_);
  if (integrator_->runs_obstacle_contacts()) {
    const IntegratorContacts contacts = integrator_->take_obstacle_contacts();
    statistics.contacts = contacts.last;
    statistics.contact_steps += contacts.steps;
    statistics.max_in_a_step = std::max(statistics.max_in_a_step, contacts.most);
  } else {
    statistics.contacts = counts.obstacles.contacts;
    statistics.contact_steps += counts.obstacles.contacts;
    statistics.max_in_a_step = std::max(statistics.max_in_a_step, counts.obstacles.contacts);
  }
  if (integrator_->runs_self_contacts()) {
    const IntegratorSelfContacts self = integrator_->take_self_contacts();
    statistics.self_contacts = self.last;
    statistics.self_contact_steps += self.steps;
    statistics.self_max_in_a_step = std::max(statistics.self_max_in_a_step, self.most);
    statistics.self_impacts += self.impacts;
    statistics.self_impact_zones += self.zones;
    statistics.self_unresolved += self.unresolved;
    return;
  }
  statistics.self_contacts = counts.self.contacts;
  statistics.self_contact_steps += counts.self.contacts;
  statistics.self_max_in_a_step = std::max(statistics.self_max_in_a_step, counts.self.contacts);
  statistics.self_impacts += counts.self.impacts;
  statistics.self_impact_zones += counts.self.zones;
  statistics.self_unresolved += counts.self.unresolved;
}

void Simulation::move_anchors() {
  StageTimer timer(profile_, StepStage::anchors);
  apply_anchor_events(*model_, state_);
}

void Simulation::apply_events() {
  StageTimer timer(profile_, StepStage::events);
  // A device integrator applied the laws after each of its steps (sim/backend.h).
  if (integrator_->runs_spring_events()) {
    const IntegratorEvents counts = integrator_->take_spring_events(*model_);
    event_totals_.breaks += counts.breaks;
    event_totals_.yields += counts.yields;
    event_totals_.creases += counts.creases;
    return;
  }
  const SpringEventCounts counts = spring_events_.apply(*model_, state_, threads_);
  event_totals_.breaks += counts.breaks;
  event_totals_.yields += counts.yields;
  event_totals_.creases += counts.creases;
}

bool Simulation::check() {
  StageTimer timer(profile_, StepStage::checks);
  // After a device's advance, the device checks the state and sums its energies where it lives
  // (Integrator::check_state), and the host's check runs only to name what failed. Between the
  // single steps of a device that the host works between, the host checks, as on the CPU.
  if (!host_works_between_steps()) {
    const std::optional<StateChecks> checks = integrator_->check_state(state_, settings_.explosion_stretch);
    if (checks && !checks->failed) {
      checked_energy_ = checks->energy;  // what energy() gives until the state or the model changes
      return true;
    }
  }
  check_state();
  return !failure_;
}

namespace {

// The first index in [0, count) where bad(i), or count: blocks in parallel, the first block's
// find wins, so the answer does not depend on the thread count.
template <typename Bad>
std::size_t first_where(std::size_t count, int threads, Bad&& bad) {
  constexpr std::size_t kBlock = 4096;
  const std::size_t blocks = (count + kBlock - 1) / kBlock;
  std::vector<std::size_t> first(blocks, count);
  parallel_for(blocks, threads, [&](std::size_t block) {
    const std::size_t begin = block * kBlock;
    const std::size_t end = std::min(count, begin + kBlock);
    // Whether the block has one, in a loop without an exit (which the compiler may vectorise and
    // the branch predictor never misses); only then where.
    bool any = false;
    for (std::size_t i = begin; i < end; ++i) any |= bad(i);
    if (!any) return;
    for (std::size_t i = begin; i < end; ++i) {
      if (bad(i)) {
        first[block] = i;
        return;
      }
    }
  });
  for (std::size_t found : first) {
    if (found < count) return found;
  }
  return count;
}

}  // namespace

void Simulation::check_state() {
  const ClothModel& model = *model_;
  const std::size_t particle = first_where(model.particle_count(), threads_, [&](std::size_t p) {
    return !is_finite(state_.position[p]) || !is_finite(state_.velocity[p]);
  });
  if (particle < model.particle_count()) {
    const std::string where = model.describe_particle(particle);
    fail(where, "non-finite state at " + where + ": position " + diagnostic_vector(state_.position[particle]) +
                    ", velocity " + diagnostic_vector(state_.velocity[particle]));
    return;
  }
  const auto stretch = [&](std::size_t e) {
    const auto [a, b] = model.connector_particles[e];
    return norm(state_.position[b] - state_.position[a]) / model.connector_rest_length[e];
  };
  // The ends of a broken connector may drift apart without limit: torn pieces fall away. Squared,
  // |x_b - x_a|^2 > (limit l0)^2, the test needs no root or division per connector (it runs after
  // every step).
  const double limit = settings_.explosion_stretch;
  const std::size_t e = first_where(model.connector_count(), threads_, [&](std::size_t c) {
    const auto [a, b] = model.connector_particles[c];
    const double reach = limit * model.connector_rest_length[c];
    return model.connector_live[c] != 0 && squared_norm(state_.position[b] - state_.position[a]) > reach * reach;
  });
  if (e < model.connector_count()) {
    const auto [a, b] = model.connector_particles[e];
    const std::string where = "connector " + std::to_string(e) + " between " + model.describe_particle(a) + " and " +
                              model.describe_particle(b);
    fail(where, "the simulation exploded: " + where + " is " + diagnostic_number(stretch(e)) +
                    " times its rest length (limit " + diagnostic_number(settings_.explosion_stretch) + ")");
  }
}

void Simulation::fail(std::string element, const std::string& message) {
  Diagnosis diagnosis;
  diagnosis.time = state_.time;
  diagnosis.step = integrator_ ? integrator_->stats().accepted_steps : 0;
  diagnosis.element = std::move(element);
  diagnosis.message =
      "at t = " + diagnostic_number(diagnosis.time) + " s (step " + std::to_string(diagnosis.step) + "): " + message;
  failure_ = std::move(diagnosis);
}

std::size_t Simulation::memory_bytes() const {
  return model_->bytes() + (state_.position.capacity() + state_.velocity.capacity()) * sizeof(Vec3) +
         integrator_->workspace_bytes() + spring_events_.bytes() + collision_stage_->bytes();
}

EnergyReport Simulation::energy() const {
  return checked_energy_ ? *checked_energy_ : compute_energy(*model_, state_, settings_.terms, threads_);
}

EnergyBalance Simulation::energy_balance() const {
  EnergyBalance balance;
  balance.energy = energy();
  balance.initial_total = initial_energy_;
  balance.damping_work = state_.damping_work;
  balance.drag_work = state_.drag_work;
  balance.anchor_work = state_.anchor_work;
  balance.edit_work = edit_work_;
  balance.plastic_work = state_.plastic_work;
  balance.fracture_work = state_.fracture_work;
  balance.contact_work = state_.contact_work;
  return balance;
}

ModelChanges Simulation::model_changes() const {
  const ClothModel& model = *model_;
  ModelChanges changes;
  changes.broken_connectors = model.broken_connector_count;
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    if (model.connector_live[e] == 0) continue;
    changes.max_plastic_strain =
        std::max(changes.max_plastic_strain,
                 std::abs(model.connector_rest_length[e] / model.connector_original_length[e] - 1.0));
  }
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    if (model.radial_live[r] == 0) {
      ++changes.broken_radials;
      continue;
    }
    changes.max_rest_angle_change =
        std::max(changes.max_rest_angle_change, std::abs(model.radial_rest_angle[r] - model.radial_original_angle[r]));
  }
  return changes;
}

IntegratorStats Simulation::integrator_stats() const { return combine(retired_stats_, integrator_->stats()); }

std::string Simulation::profile_notes() const { return integrator_->profile_notes(); }

StepProfile Simulation::profile() const {
  StepProfile integrator = retired_profile_;
  integrator += integrator_->profile();
  StepProfile profile = profile_;
  profile += integrator;
  // What the integrator times of the step's own stages (its forces; the device's events) is
  // inside the integration stage's time: the rest is integration.
  double own = 0.0;
  for (const StepStageInfo& info : kStepStages) {
    if (is_step_stage(info.stage) && info.stage != StepStage::integration) own += integrator.seconds(info.stage);
  }
  profile.set(StepStage::integration, profile_.seconds(StepStage::integration) - own);
  return profile;
}

}  // namespace clothsim
