// Simulation: owns a model, its state and an integrator, and advances to requested times.
//
// advance_to(t) reads like the algorithm it runs, one named stage after another, each timed as
// its StepStage (core/step_profile.h):
//   while the state is before t:
//     integrate: one accepted step (adaptive, never past t, an anchor event  -> forces, integration
//                or an approaching impact); on `precision: auto`, the forces'
//                precision chosen first at each window's start (sim/precision_choice.h)
//     collide:   between steps, on the accepted state: particles out of the   -> collisions
//                obstacles, then the sheet out of itself, velocities corrected
//                (collision/collision_stage.h)
//     anchors:   anchors arriving, at a keyframe, or let go (sim/anchor_events.h) -> anchors
//     events:    tearing, permanent stretching and creasing (events/), each    -> events
//                change through model/model_edits.h
//     checks:    the state is finite and not exploding                      -> checks
//   then, once per call, the blow-up check on the energy balance             -> checks
// sim/profile.h turns the profile into the table `clothsim run --profile` prints. The records it
// reports (the energy balance, contacts, changes, a failure's diagnosis) are in sim/statistics.h;
// the live edits below are defined in sim/live_edits.cpp.
// A failed check or integrator stops the simulation with a Diagnosis (time, step, element), and
// the state stays at the last good step, so a caller can still write what it has.
//
// Live editing (the viewer's panel and scripts) goes through the set_*, cut_* and *_particle
// members, called between advance_to() calls, so an edit takes effect from the next step on and
// never inside one. Every change goes through model/model_edits.h, which moves the model's
// revision; the integrator refreshes what it caches from the model and keeps its step-size
// history. Only set_integrator() makes a new integrator; statistics and the profile count across
// it. Every edit books the energy it adds or removes, so the balance stays exact across edits
// (docs/viewer.md):
//   parameter edits (stiffness, gravity, mass): EnergyBalance::edit_work += E_after - E_before,
//     the jump of potential or kinetic energy the edit causes at fixed positions and velocities;
//   anchor edits (pin, drive, a driven anchor arriving): the jump of the anchored particle's
//     velocity is the anchor's impulse, and its work 1/2 m (|v_after|^2 - |v_before|^2) goes into
//     ClothState::anchor_work like the anchor's continuous work;
//   release: the particle goes on with the velocity it has, so no energy changes;
//   cuts and the events' breaks and yields: the elastic energy they release at fixed positions
//     goes into fracture_work and plastic_work (events/).
// Rejected: resetting E(0) at each edit. The balance would then say nothing about the run before
// the edit, and a viewer's energy plot would jump.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "collision/collision_stage.h"
#include "core/step_profile.h"
#include "events/spring_events.h"
#include "forces/forces.h"
#include "integrators/integrator.h"
#include "model/cloth_model.h"
#include "model/spring_limits.h"
#include "sim/backend.h"
#include "sim/precision_choice.h"
#include "sim/statistics.h"

namespace clothsim {

struct SimulationSettings {
  IntegratorSettings integrator;
  int threads = 0;  // 0: choose from the lattice size and the idle cores (core/parallel.h)
  ForceTerms terms = kAllForceTerms;
  ForceKernel kernel = ForceKernel::automatic;  // which force implementation (forces.h)
  // A connector longer than this many times its rest length means the integration has blown up.
  double explosion_stretch = 1000.0;
  // Where the steps run (sim/backend.h): the CPU, or a Vulkan device, which takes all the steps
  // up to the next frame or event without the host (the checks then run once per advance_to()).
  BackendSettings backend;
};

// What the blow-up check's diagnosis advises for a run of `kind` whose energy balance failed.
std::string blow_up_advice(IntegratorKind kind);

class Simulation {
 public:
  // Throws BackendError when settings.backend cannot run the model (sim/backend.h): a feature it
  // does not cover, no device, not enough device memory.
  Simulation(ClothModel model, ClothState initial, const SimulationSettings& settings);
  // Movable, not copyable: what the integrator refers to (the model, the collision stage's surface
  // contacts) lives on the heap and moves with the simulation (scene/scene_simulation.h returns
  // one by value).

  // Advances to exactly `time` (>= the current time). Returns false if the simulation failed,
  // now or before; failure() then says why, and state() is the last good state.
  bool advance_to(double time);

  const ClothModel& model() const { return *model_; }
  const ClothState& state() const { return state_; }
  const SimulationSettings& settings() const { return settings_; }
  int threads() const { return threads_; }
  // Totals over the run, across set_integrator() switches (last_step is the current integrator's).
  IntegratorStats integrator_stats() const;
  // Wall time per stage of the step (core/step_profile.h), the integrator's parts included, over
  // the run and across set_integrator() switches.
  StepProfile profile() const;
  // What the integrator adds under the profile's table (Integrator::profile_notes()): the device's
  // memory traffic per attempt on the Vulkan backend; empty on the CPU.
  std::string profile_notes() const;
  // Bytes held by the model's arrays, the state and the integrator's workspace (capacity, not
  // just size): the simulation's own memory, without the process around it.
  std::size_t memory_bytes() const;
  const std::optional<Diagnosis>& failure() const { return failure_; }

  EnergyReport energy() const;
  EnergyBalance energy_balance() const;
  // The blow-up check's energy scale so far, J: what energy_balance().error() is measured against
  // (docs/cli.md, "The blow-up check").
  double energy_scale() const { return energy_scale_; }
  ModelChanges model_changes() const;
  // Breaks, yields and creases applied by the event stage so far (not counting cuts).
  const SpringEventCounts& event_totals() const { return event_totals_; }
  // Contacts with obstacles so far.
  const ContactStatistics& contact_statistics() const { return contact_statistics_; }
  // `precision: auto` frame by frame on the CPU (sim/precision_choice.h): whether the run chooses,
  // and what it chose so far.
  const PrecisionChoice& precision_choice() const { return precision_choice_; }

  // Checkpoints (io/checkpoint.h): saves the simulation into a saving archive, or restores it
  // from a loading one, between advance_to() calls. Saved: the state, the model's changes since
  // it was built (model/model_state.h), the integrator's controller state, the work integrals,
  // the blow-up check's scale and the run's counters; not the wall-time profile. Restore into a
  // simulation built from the same scene (and so the same model and settings): the result then
  // goes on exactly as the saved one would have, bit for bit. A failed simulation cannot be
  // saved (std::logic_error). Restoring throws std::runtime_error naming the field when the
  // archive does not fit; the simulation is then unusable.
  void transfer_state(StateArchive& archive);

  // Live parameter edits, between advance_to() calls (see the top of this file). Values must be
  // valid (the caller checks input against the parameter registry, scene/parameters.h).
  //
  // Stiffness and damping of every spring of `family`.
  void set_spring_parameters(SpringFamily family, const SpringParameters& parameters);
  // Gravity and air drag.
  void set_environment(const Environment& environment);
  // Every particle's mass, kg (> 0); anchored particles stay anchored.
  void set_particle_mass(double mass);
  // A new integrator (kind, tolerances, step) that goes on from the current state. Statistics
  // and the profile keep counting across the switch. Throws BackendError for a method the
  // backend does not run (the old integrator then stays).
  void set_integrator(const IntegratorSettings& settings);
  // Break, yield and crease limits of every spring (model/spring_limits.h). Hardened yields
  // start again from limits.yield_strain; broken springs stay broken and rest values stay.
  // Throws BackendError, changing nothing, for limits the backend does not run (the Vulkan
  // backend's general path).
  void set_spring_limits(const SpringLimits& limits);
  // Breaks the given connectors now, with the radial springs that use them (a cut with the
  // mouse); their elastic energy goes into fracture_work. Returns how many were intact.
  std::size_t cut_connectors(std::span<const std::uint32_t> connectors);

  // Runtime anchors (the viewer's mouse and pins, scripted drags).
  //
  // Holds `particle` where it is now, at rest (anchoring it if it was free).
  void pin_particle(std::uint32_t particle);
  // Moves `particle` in a straight line at constant velocity from where it is now to `target`,
  // arriving at simulated time `arrival_time` (> the current time), and holds it there after.
  // Re-aiming a driven particle between frames makes it follow a moving cursor. Steps never
  // cross the arrival time.
  void drive_particle(std::uint32_t particle, const Vec3& target, double arrival_time);
  // Puts an anchored particle at `position` at once and holds it there, without simulated time
  // passing (a drag in a paused viewer). The energy jump is booked as edit work.
  void place_particle(std::uint32_t particle, const Vec3& position);
  // Frees an anchored particle: it goes on with its current velocity, and its inverse mass is
  // restored. Returns false if it was free.
  bool release_particle(std::uint32_t particle);

  // Obstacles and self-collision, live (the viewer's hand on a sphere, its self-collision switch;
  // model/model_edits.h). None changes the energy at the time of the edit: a moved obstacle acts
  // through the collision stage, which books what it does as contact work.
  //
  // Self-collision on or off from the next step on. Throws BackendError, changing nothing, where
  // the backend does not run it; so does add_collider().
  void set_self_collision(bool on);
  // Appends an obstacle; returns its index in model().colliders.
  std::size_t add_collider(const Collider& collider);
  // Moves collider `collider` rigidly in a straight line by `displacement` from where it is now,
  // arriving at simulated time `arrival_time` (> the current time), and holds it there after; the
  // sheet feels it as a moving obstacle (model/model_edits.h, drive_collider).
  void drive_collider(std::size_t collider, const Vec3& displacement, double arrival_time);
  // Moves collider `collider` by `displacement` at once (a drag while paused).
  void place_collider(std::size_t collider, const Vec3& displacement);

 private:
  void check_state();
  // The blow-up check on the energy balance, after advance_to()'s steps; false once failed.
  bool check_energy_balance();
  void fail(std::string element, const std::string& message);
  // A new integrator for the current model on the run's backend and settings (the constructor's,
  // a restored checkpoint's, a restart's), pointed at the collision stage's surface contacts; the
  // precision choice configured for it (its statistics kept).
  std::unique_ptr<Integrator> new_integrator();
  // Replaces the integrator with a new one for the current model and settings_.integrator,
  // keeping the statistics of the old one.
  void restart_integrator();
  // Throws BackendError when the backend cannot run these features (an edit about to be made:
  // the model's features with the edit's change).
  void require_backend_runs(const BackendFeatures& features) const;

  // The stages of advance_to(), in order. Those that can fail return false when the simulation
  // failed. begin_collisions() keeps the step's start for the swept tests and returns the time of
  // the nearest approaching impact (or +infinity), which the step does not cross.
  double begin_collisions();
  bool integrate(double time);
  // Whether the host runs a stage between steps that the integrator does not run itself (the event
  // stage's laws, the collision stage): then a device integrator is asked for one step at a time.
  bool host_works_between_steps() const;
  void collide();
  void move_anchors();
  void apply_events();
  bool check();

  std::unique_ptr<ClothModel> model_;  // on the heap: the integrator keeps a reference to it
  ClothState state_;
  SimulationSettings settings_;
  int threads_ = 1;
  std::unique_ptr<Integrator> integrator_;
  PrecisionChoice precision_choice_;  // configured with each new integrator
  IntegratorStats retired_stats_;     // summed over integrators replaced by set_integrator()
  StepProfile retired_profile_;       // their stages' times
  double initial_energy_ = 0.0;
  // The blow-up check: the energies at the start, and the largest energy scale seen (J).
  EnergyReport initial_report_;
  double energy_scale_ = 0.0;
  double released_ = 0.0;               // J, the largest change of gravitational energy so far
  double moved_work_ = 0.0;             // J, the work integrals' changes summed in magnitude over checks
  std::array<double, 5> last_works_{};  // anchor, contact, edit, plastic, fracture work at the last check
  double edit_work_ = 0.0;              // J, see EnergyBalance::edit_work
  StepProfile profile_;
  SpringEvents spring_events_;
  SpringEventCounts event_totals_;  // over the run
  // On the heap: the integrator keeps a pointer to its surface contacts, which must not move
  // when the Simulation does.
  std::unique_ptr<CollisionStage> collision_stage_ = std::make_unique<CollisionStage>();
  ContactStatistics contact_statistics_;
  std::optional<Diagnosis> failure_;
  // The energies the last passed blow-up check computed, which energy() returns instead of
  // computing them again (a run writes each frame's right after the check): reset by advance_to()
  // and by every edit, transfer_state() included, before it changes anything.
  std::optional<EnergyReport> checked_energy_;
};

}  // namespace clothsim
