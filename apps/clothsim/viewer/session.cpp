#include "viewer/session.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/assert.h"
#include "core/error.h"
#include "core/timer.h"
#include "scene/parameters.h"
#include "scene/scene_simulation.h"
#include "scene/validate_scene.h"
#include "viewer/interaction.h"

namespace clothsim::viewer {

Session::Session(SceneSpec scene, MemoryAllowance memory) : scene_(std::move(scene)), memory_(std::move(memory)) {
  build();
}

void Session::build() {
  simulation_ = make_unique_simulation(scene_, memory_);
  if (edited_limits_) simulation_->set_spring_limits(*edited_limits_);
  if (edited_self_collision_) simulation_->set_self_collision(*edited_self_collision_);
  for (const Collider& sphere : added_spheres_) simulation_->add_collider(sphere);
}

void Session::set_self_collision(bool on) {
  const ClothModel& model = simulation_->model();
  const double limit = self_collision_thickness_limit(model.spacing);
  if (on && model.collision.thickness >= limit) {
    throw InputError("self-collision", "collision.thickness",
                     "must be below half the lattice spacing (" + format_number(limit) +
                         " m) for self-collision, got " + format_number(model.collision.thickness) +
                         " (lower it with --thickness)");
  }
  simulation_->set_self_collision(on);
  edited_self_collision_ = on;
}

std::size_t Session::add_sphere(const Vec3& center, double radius) {
  CLOTHSIM_ASSERT(radius > 0.0 && is_finite(center), "a sphere has a centre and a positive radius");
  Collider sphere;
  sphere.shape = ColliderShape::sphere;
  // Given at the current time: at rest, its t = 0 shape is where it is now.
  sphere.center = center;
  sphere.radius = radius;
  added_spheres_.push_back(sphere);
  return simulation_->add_collider(sphere);
}

std::vector<std::size_t> Session::spheres() const {
  std::vector<std::size_t> indices;
  const std::vector<Collider>& colliders = simulation_->model().colliders;
  for (std::size_t c = 0; c < colliders.size(); ++c) {
    if (colliders[c].shape == ColliderShape::sphere) indices.push_back(c);
  }
  return indices;
}

Vec3 Session::sphere_center(std::size_t collider) const {
  const Collider& sphere = simulation_->model().colliders.at(collider);
  return sphere.center + collider_offset(sphere, time());
}

void Session::move_sphere(std::size_t collider, const Vec3& target, double duration) {
  CLOTHSIM_ASSERT(simulation_->model().colliders.at(collider).shape == ColliderShape::sphere, "a sphere is moved");
  const Vec3 displacement = target - sphere_center(collider);
  const double arrival = time() + duration;
  if (arrival > time() && playing_) {  // as drag(): a duration lost to rounding places instead
    simulation_->drive_collider(collider, displacement, arrival);
  } else {
    simulation_->place_collider(collider, displacement);
  }
}

std::size_t Session::cut(std::span<const std::uint32_t> connectors) { return simulation_->cut_connectors(connectors); }

std::size_t Session::cut_in_lattice(const std::array<double, 2>& from, const std::array<double, 2>& to) {
  return cut(connectors_crossed_in_lattice(simulation_->model(), from, to));
}

void Session::set_spring_limits(const SpringLimits& limits) {
  CLOTHSIM_ASSERT(check_spring_limits(limits).empty(), "spring limits are checked by the caller");
  simulation_->set_spring_limits(limits);
  edited_limits_ = limits;
}

std::string check_spring_limits(const SpringLimits& limits) {
  if (!(limits.break_strain > 0.0)) return "break strain must be > 0";
  if (!(limits.break_strain_variation >= 0.0 && limits.break_strain_variation < 1.0)) {
    return "break strain variation must be in [0, 1)";
  }
  if (!(limits.yield_strain > 0.0)) return "yield strain must be > 0";
  if (!(limits.hardening >= 0.0) || std::isinf(limits.hardening)) return "hardening must be a number >= 0";
  if (!(limits.adjacent_yield_angle >= 0.0) || !(limits.opposite_yield_angle >= 0.0)) {
    return "yield angles must be >= 0";
  }
  // Tearing is measured against the original length; a yield above the break strain would never
  // be reached (events/spring_events.h).
  if (yields_after_breaking(limits.yield_strain, limits.break_strain)) {
    return "the yield strain must not exceed the break strain";
  }
  return {};
}

void Session::reset() {
  build();
  held_.clear();
  energy_history_.clear();
}

double Session::advance(double duration, double work_budget, double piece) {
  if (failed() || duration <= 0.0) return 0.0;
  const double start = time();
  const double end = start + duration;
  if (work_budget <= 0.0 || piece <= 0.0) {
    simulation_->advance_to(end);
    return time() - start;
  }
  const Stopwatch watch;
  while (time() < end) {
    if (!simulation_->advance_to(std::min(end, time() + piece))) break;
    if (watch.seconds() >= work_budget) break;
  }
  return time() - start;
}

void Session::set_parameters(const std::vector<std::pair<std::string, std::string>>& assignments,
                             const std::string& source) {
  SceneSpec edited = scene_;
  for (const auto& [key, value] : assignments) {
    if (!is_live_parameter(key)) {
      throw InputError(source, key, "cannot change while the simulation runs; live keys: " + live_parameter_list());
    }
    set_scene_field(edited, key, value, source);
  }
  validate_scene(edited, source);
  set_live_parameters(edited);
}

void Session::set_live_parameters(const SceneSpec& edited) {
  apply_live_parameters(scene_, edited, *simulation_);
  scene_.lattice.connector = edited.lattice.connector;
  scene_.lattice.adjacent = edited.lattice.adjacent;
  scene_.lattice.opposite = edited.lattice.opposite;
  scene_.lattice.particle_mass = edited.lattice.particle_mass;
  scene_.environment = edited.environment;
  scene_.integrator = edited.integrator;
}

bool Session::is_pinned(std::uint32_t particle) const {
  return simulation_->model().is_anchored(particle) && !is_held(particle);
}

void Session::drag(std::uint32_t particle, const Vec3& target, double duration) {
  CLOTHSIM_ASSERT(particle < simulation_->model().particle_count(), "dragged particle is in the lattice");
  if (!is_held(particle)) held_.emplace(particle, simulation_->model().is_anchored(particle));
  const double arrival = time() + duration;
  if (arrival > time() && playing_) {  // a duration lost to rounding next to time() places instead
    simulation_->drive_particle(particle, target, arrival);
    return;
  }
  if (!simulation_->model().is_anchored(particle)) simulation_->pin_particle(particle);
  simulation_->place_particle(particle, target);
}

void Session::release(std::uint32_t particle) {
  const auto held = held_.find(particle);
  if (held == held_.end()) return;
  const bool was_pinned = held->second;
  held_.erase(held);
  if (was_pinned) {
    simulation_->pin_particle(particle);
  } else {
    simulation_->release_particle(particle);
  }
}

void Session::pin(std::uint32_t particle) {
  held_.erase(particle);
  simulation_->pin_particle(particle);
}

void Session::unpin(std::uint32_t particle) {
  held_.erase(particle);
  simulation_->release_particle(particle);
}

void Session::record_energy(double window) {
  if (!energy_history_.empty() && energy_history_.back().time == time()) return;
  const EnergyReport energy = simulation_->energy();
  EnergySample sample;
  sample.time = time();
  sample.kinetic = energy.kinetic;
  sample.total = energy.total();
  sample.potential = sample.total - sample.kinetic;
  energy_history_.push_back(sample);
  while (energy_history_.front().time < sample.time - window) energy_history_.pop_front();
}

std::uint32_t Session::particle(int row, int col) const {
  CLOTHSIM_ASSERT(row >= 0 && row < scene_.lattice.rows && col >= 0 && col < scene_.lattice.cols,
                  "particle inside the lattice");
  return lattice_index(scene_.lattice.cols, row, col);
}

ScriptPlayer::ScriptPlayer(Script script, double frame_time) : script_(std::move(script)), frame_time_(frame_time) {
  order_.resize(script_.events.size());
  for (std::size_t i = 0; i < order_.size(); ++i) order_[i] = i;
  std::stable_sort(order_.begin(), order_.end(), [this](std::size_t a, std::size_t b) {
    return script_.events[a].firing_frame(frame_time_) < script_.events[b].firing_frame(frame_time_);
  });
}

std::uint64_t ScriptPlayer::last_event_frame() const {
  return order_.empty() ? 0 : script_.events[order_.back()].firing_frame(frame_time_);
}

ScriptPlayer::FrameRequests ScriptPlayer::fire(std::uint64_t frame, Session& session) {
  FrameRequests requests;
  while (next_ < order_.size() && script_.events[order_[next_]].firing_frame(frame_time_) <= frame) {
    const ScriptEvent& event = script_.events[order_[next_++]];
    switch (event.action) {
      case ScriptAction::drag: session.drag(session.particle(event.row, event.col), event.to, event.duration); break;
      case ScriptAction::release: session.release(session.particle(event.row, event.col)); break;
      case ScriptAction::pin: session.pin(session.particle(event.row, event.col)); break;
      case ScriptAction::unpin: session.unpin(session.particle(event.row, event.col)); break;
      case ScriptAction::pause: session.set_playing(false); break;
      case ScriptAction::play: session.set_playing(true); break;
      case ScriptAction::set:
        session.set_parameters(event.assignments, script_.source + ": events[" + std::to_string(event.index) + "].set");
        break;
      case ScriptAction::cut: session.cut_in_lattice(event.cut_from, event.cut_to); break;
      case ScriptAction::self_collision: session.set_self_collision(event.on); break;
      case ScriptAction::add_sphere: session.add_sphere(event.center, event.radius); break;
      case ScriptAction::move_sphere: {
        const std::vector<std::size_t> spheres = session.spheres();
        CLOTHSIM_ASSERT(event.sphere < spheres.size(), "check_script() checked the sphere's number");
        session.move_sphere(spheres[event.sphere], event.to, event.duration);
        break;
      }
      case ScriptAction::screenshot: requests.screenshots.push_back(event.path); break;
      case ScriptAction::quit: requests.quit = true; break;
    }
  }
  return requests;
}

}  // namespace clothsim::viewer
