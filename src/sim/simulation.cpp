#include "sim/simulation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/assert.h"
#include "core/parallel.h"
#include "core/timer.h"
#include "model/model_edits.h"

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
  integrator_ = make_backend_integrator(*model_, settings.integrator,
                                        ForceOptions{settings.terms, threads_, settings.kernel}, settings.backend);
  integrator_->set_surface_contacts(&collision_stage_->surface_contacts());
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

bool Simulation::advance_to(double time) {
  if (failure_) return false;
  CLOTHSIM_ASSERT(time >= state_.time, "advance_to() cannot go back in time");
  while (state_.time < time) {
    double step_end = time;
    {
      // The collision stage's swept tests start from the positions before the step, and an
      // approaching impact limits the step (collision/obstacle_contacts.h).
      ScopedTimer timer(profile_.collisions);
      step_end = std::min(time, collision_stage_->begin_step(*model_, state_, threads_));
    }
    if (!integrate(step_end)) return false;
    collide();
    apply_events();
    if (!check()) return false;
  }
  return check_energy_balance();
}

bool Simulation::check_energy_balance() {
  ScopedTimer timer(profile_.checks);
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
  if (!(error > limit * energy_scale_)) return true;
  // The worst element: the fastest particle.
  std::size_t fastest = 0;
  for (std::size_t p = 1; p < state_.velocity.size(); ++p) {
    if (squared_norm(state_.velocity[p]) > squared_norm(state_.velocity[fastest])) fastest = p;
  }
  const std::string where = model_->describe_particle(fastest);
  fail(where, "the integration has blown up: the energy balance is off by " + format_number(error) +
                  " J, more than integrator.energy_error_limit = " + format_number(limit) +
                  " times the run's energy scale of " + format_number(energy_scale_) + " J; the fastest particle is " +
                  where + " at " + format_number(norm(state_.velocity[fastest])) + " m/s. Try a smaller --time-step, " +
                  "or --integrator rkf45 (adaptive) or implicit-euler (stable for any step).");
  return false;
}

bool Simulation::integrate(double time) {
  Stopwatch watch;
  const double force_before = integrator_->force_seconds();
  // Anchor events (a driven anchor arriving, an anchor letting go) are never crossed by a step.
  // One step on the CPU; on a device, every step up to the limit (nothing the host does between
  // steps applies there: sim/backend.h keeps such features off it).
  const StepOutcome outcome = integrator_->advance(state_, std::min(time, next_anchor_event()));
  const double force = integrator_->force_seconds() - force_before;
  profile_.forces += force;
  profile_.integration += watch.seconds() - force;

  if (outcome.status == StepStatus::step_underflow) {
    const std::string where = model_->describe_particle(outcome.particle);
    fail(where,
         std::string(outcome.non_finite_error ? "forces became non-finite" : "step size underflow") + ": " +
             std::string(to_string(settings_.integrator.kind)) + " needed a step of " + format_number(outcome.step) +
             " s, below min_step = " + format_number(settings_.integrator.min_step) + " s; the largest error is at " +
             where + ". The state is blowing up, or the problem is too stiff for this tolerance.");
    return false;
  }
  if (outcome.status == StepStatus::non_finite) {
    const std::string where = model_->describe_particle(outcome.particle);
    fail(where, "the state became non-finite at " + where + " during a step of " + format_number(outcome.step) +
                    " s; the time step is too large for this material (try a smaller --time-step or rkf45).");
    return false;
  }
  return true;
}

void Simulation::collide() {
  ScopedTimer timer(profile_.collisions);
  const CollisionCounts counts = collision_stage_->apply(*model_, state_, settings_.terms, threads_);
  ContactStatistics& statistics = contact_statistics_;
  statistics.last_step = counts.obstacles.contacts;
  statistics.total += counts.obstacles.contacts;
  statistics.max_in_a_step = std::max(statistics.max_in_a_step, counts.obstacles.contacts);
  statistics.self_last_step = counts.self.contacts;
  statistics.self_total += counts.self.contacts;
  statistics.self_max_in_a_step = std::max(statistics.self_max_in_a_step, counts.self.contacts);
  statistics.self_impacts += counts.self.impacts;
  statistics.self_zones += counts.self.zones;
  statistics.self_unresolved += counts.self.unresolved;
}

void Simulation::apply_events() {
  ScopedTimer timer(profile_.events);
  stop_arrived_anchors();
  book_anchor_keys();
  release_due_anchors();
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
  ScopedTimer timer(profile_.checks);
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
    const std::size_t end = std::min(count, (block + 1) * kBlock);
    for (std::size_t i = block * kBlock; i < end; ++i) {
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
    fail(where, "non-finite state at " + where + ": position " + format_vector(state_.position[particle]) +
                    ", velocity " + format_vector(state_.velocity[particle]));
    return;
  }
  const auto stretch = [&](std::size_t e) {
    const auto [a, b] = model.connector_particles[e];
    return norm(state_.position[b] - state_.position[a]) / model.connector_rest_length[e];
  };
  // The ends of a broken connector may drift apart without limit: torn pieces fall away.
  const std::size_t e = first_where(model.connector_count(), threads_, [&](std::size_t c) {
    return model.connector_live[c] != 0 && stretch(c) > settings_.explosion_stretch;
  });
  if (e < model.connector_count()) {
    const auto [a, b] = model.connector_particles[e];
    const std::string where = "connector " + std::to_string(e) + " between " + model.describe_particle(a) + " and " +
                              model.describe_particle(b);
    fail(where, "the simulation exploded: " + where + " is " + format_number(stretch(e)) +
                    " times its rest length (limit " + format_number(settings_.explosion_stretch) + ")");
  }
}

void Simulation::fail(std::string element, std::string message) {
  Diagnosis diagnosis;
  diagnosis.time = state_.time;
  diagnosis.step = integrator_ ? integrator_->stats().accepted_steps : 0;
  diagnosis.element = std::move(element);
  diagnosis.message =
      "at t = " + format_number(diagnosis.time) + " s (step " + std::to_string(diagnosis.step) + "): " + message;
  failure_ = std::move(diagnosis);
}

std::size_t Simulation::memory_bytes() const {
  return model_->bytes() + (state_.position.capacity() + state_.velocity.capacity()) * sizeof(Vec3) +
         integrator_->workspace_bytes() + spring_events_.bytes() + collision_stage_->bytes();
}

EnergyReport Simulation::energy() const { return compute_energy(*model_, state_, settings_.terms, threads_); }

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

IntegratorStats Simulation::integrator_stats() const {
  IntegratorStats total = integrator_->stats();
  total.accepted_steps += retired_stats_.accepted_steps;
  total.rejected_steps += retired_stats_.rejected_steps;
  total.force_evaluations += retired_stats_.force_evaluations;
  total.smallest_step = std::min(total.smallest_step, retired_stats_.smallest_step);
  total.largest_step = std::max(total.largest_step, retired_stats_.largest_step);
  return total;
}

// ---------------------------------------------------------------------------------------------
// Live editing.

void Simulation::set_spring_parameters(SpringFamily family, const SpringParameters& parameters) {
  const double before = energy().total();
  set_spring_family(*model_, family, parameters);
  edit_work_ += energy().total() - before;
}

void Simulation::set_environment(const Environment& environment) {
  const double before = energy().total();
  clothsim::set_environment(*model_, environment);
  edit_work_ += energy().total() - before;
}

void Simulation::require_backend_runs(const BackendFeatures& features) const {
  const std::string unsupported = unsupported_by_backend(features, settings_.backend);
  if (!unsupported.empty()) throw BackendError(backend_refusal(unsupported, settings_.backend));
}

void Simulation::set_spring_limits(const SpringLimits& limits) {
  BackendFeatures features = features_of(*model_, settings_.integrator);
  features.limits = limits;
  require_backend_runs(features);
  apply_spring_limits(*model_, limits);
}

std::size_t Simulation::cut_connectors(std::span<const std::uint32_t> connectors) {
  std::size_t cut = 0;
  for (std::uint32_t e : connectors) cut += tear_connector(*model_, state_, e) ? 1 : 0;
  return cut;
}

void Simulation::set_particle_mass(double mass) {
  const double before = energy().total();
  clothsim::set_particle_mass(*model_, mass);
  edit_work_ += energy().total() - before;
}

void Simulation::set_integrator(const IntegratorSettings& settings) {
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
  std::unique_ptr<Integrator> next = make_backend_integrator(
      *model_, settings_.integrator, ForceOptions{settings_.terms, threads_, settings_.kernel}, settings_.backend);
  retired_stats_ = integrator_stats();
  integrator_ = std::move(next);
  integrator_->set_surface_contacts(&collision_stage_->surface_contacts());
}

void Simulation::hold_on_path(std::uint32_t particle, const AnchorPath& path) {
  const Vec3 before = state_.velocity[particle];
  set_anchor(*model_, particle, path);
  state_.position[particle] = path.position(state_.time);
  state_.velocity[particle] = path.velocity_at(state_.time);
  state_.anchor_work +=
      0.5 * model_->particle_mass[particle] * (squared_norm(state_.velocity[particle]) - squared_norm(before));
}

void Simulation::pin_particle(std::uint32_t particle) {
  CLOTHSIM_ASSERT(particle < model_->particle_count(), "pinned particle is in the lattice");
  hold_on_path(particle, AnchorPath::fixed_at(state_.position[particle]));
}

void Simulation::drive_particle(std::uint32_t particle, const Vec3& target, double arrival_time) {
  CLOTHSIM_ASSERT(particle < model_->particle_count(), "driven particle is in the lattice");
  CLOTHSIM_ASSERT(arrival_time > state_.time, "a driven particle arrives after the current time");
  AnchorPath path;
  path.kind = AnchorPathKind::driven;
  path.origin = state_.position[particle];
  path.start_time = state_.time;
  path.end_time = arrival_time;
  path.velocity = (target - path.origin) / (arrival_time - state_.time);
  hold_on_path(particle, path);
}

void Simulation::place_particle(std::uint32_t particle, const Vec3& position) {
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
  CLOTHSIM_ASSERT(particle < model_->particle_count(), "released particle is in the lattice");
  return remove_anchor(*model_, particle);
}

void Simulation::set_self_collision(bool on) {
  BackendFeatures features = features_of(*model_, settings_.integrator);
  features.self_collision = on;
  require_backend_runs(features);
  clothsim::set_self_collision(*model_, on);
}

std::size_t Simulation::add_collider(const Collider& collider) {
  BackendFeatures features = features_of(*model_, settings_.integrator);
  features.colliders = true;
  require_backend_runs(features);
  return clothsim::add_collider(*model_, collider);
}

void Simulation::drive_collider(std::size_t collider, const Vec3& displacement, double arrival_time) {
  clothsim::drive_collider(*model_, collider, displacement, state_.time, arrival_time);
}

void Simulation::place_collider(std::size_t collider, const Vec3& displacement) {
  clothsim::place_collider(*model_, collider, displacement, state_.time);
}

double Simulation::next_anchor_event() const {
  double next = std::numeric_limits<double>::infinity();
  for (const Anchor& anchor : model_->anchors) {
    const AnchorPath& path = anchor.path;
    if (path.kind == AnchorPathKind::driven && path.velocity != Vec3{} && path.end_time > state_.time) {
      next = std::min(next, path.end_time);
    }
    if (anchor.release_time > state_.time) next = std::min(next, anchor.release_time);
    // A keyframed path's keys are velocity discontinuities (+inf for other kinds).
    next = std::min(next, path.next_key_after(state_.time));
  }
  return next;
}

void Simulation::book_anchor_keys() {
  for (const Anchor& anchor : model_->anchors) {
    const Vec3 before = anchor.path.velocity_before(state_.time);
    const Vec3 after = anchor.path.velocity_at(state_.time);
    if (before == after) continue;
    // The step that ended here left the particle on the new segment's velocity (its path's
    // velocity at this time); the jump is the anchor's impulse.
    state_.anchor_work += 0.5 * model_->particle_mass[anchor.particle] * (squared_norm(after) - squared_norm(before));
  }
}

void Simulation::release_due_anchors() {
  // remove_anchor() moves the last anchor into the freed slot, so scan from the back.
  for (std::size_t i = model_->anchors.size(); i-- > 0;) {
    if (i < model_->anchors.size() && model_->anchors[i].release_time <= state_.time) {
      remove_anchor(*model_, model_->anchors[i].particle);
    }
  }
}

void Simulation::stop_arrived_anchors() {
  for (const Anchor& anchor : model_->anchors) {
    const AnchorPath& path = anchor.path;
    if (path.kind != AnchorPathKind::driven || path.velocity == Vec3{} || path.end_time > state_.time) continue;
    AnchorPath held;
    held.kind = AnchorPathKind::driven;
    held.origin = path.position(path.end_time);
    held.start_time = path.end_time;
    // hold_on_path() only rewrites this anchor's path, so the loop's iteration stays valid.
    hold_on_path(anchor.particle, held);
  }
}

}  // namespace clothsim
