// What the viewer does, without the window: a Session owns the scene (with its live edits) and
// the Simulation, plays and pauses, advances under a wall-time budget, holds particles for the
// mouse and for scripts, and keeps the energy history for the plot. ScriptPlayer fires a
// script's events into a Session frame by frame. The window (viewer/viewer_window.h) maps input
// onto these calls and draws; tests drive them directly, with no display.
//
// The hand: a particle that is dragged (by the mouse or a script's "drag") is a driven anchor
// (Simulation::drive_particle): it moves in a straight line to its target over the given
// simulated time, and the springs and the energy balance feel it as they would a real hand. On
// release it is freed with the velocity it has, or, if it was pinned before the drag, pinned
// where it was let go. In a paused simulation there is no time to move in, so a drag places the
// particle at once (Simulation::place_particle).
//
// The knife: a cut breaks connectors now (Simulation::cut_connectors), by the mouse (the screen
// segments of viewer/interaction.h) or by a script's "cut" (a segment in rest-lattice
// coordinates). Spring limits (where the sheet tears, yields and creases) are edited live with
// set_spring_limits(); the edited limits outlive a reset, like the other live edits, until the
// scene itself carries them.
//
// Obstacles: self-collision is switched on and off live (set_self_collision), spheres are added
// (add_sphere) and moved by the hand (move_sphere). A moved sphere is driven as a dragged
// particle is: in a straight line to its target over the given simulated time
// (Simulation::drive_collider), so the collision stage sees it move and it pushes the sheet
// instead of jumping through it; paused, it is placed at once. The switch and the added spheres
// outlive a reset (kept here, not in the scene, whose checks refuse collision.self until the
// self-collision stage lands); where the hand moved a sphere does not: a reset puts every sphere
// back where it started.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "scene/scene.h"
#include "scene/scene_memory.h"
#include "sim/simulation.h"
#include "viewer/script.h"

namespace clothsim::viewer {

struct EnergySample {
  double time = 0.0;       // s, simulated
  double kinetic = 0.0;    // J
  double potential = 0.0;  // J: gravity, connector and radial springs
  double total = 0.0;      // J
};

class Session {
 public:
  // Builds the simulation of `scene` (validated by the caller), within `memory` (make_simulation;
  // the command passes its own check's). Throws InputError if the model cannot be built.
  explicit Session(SceneSpec scene, MemoryAllowance memory = {});

  // The scene with the live edits made so far (a reset starts from it).
  const SceneSpec& scene() const { return scene_; }
  const Simulation& simulation() const { return *simulation_; }
  double time() const { return simulation_->state().time; }
  bool failed() const { return simulation_->failure().has_value(); }

  bool playing() const { return playing_; }
  void set_playing(bool playing) { playing_ = playing; }

  // Back to the scene's initial state and anchors, keeping the live parameter edits; lets go of
  // every held particle and clears the energy history.
  void reset();

  // Advances the simulation by `duration` s of simulated time, in pieces of at most `piece` s,
  // and stops after the piece during which `work_budget` s of wall time ran out (0: no budget,
  // always the whole duration in one advance_to, so scripted runs are reproducible). Returns the
  // simulated time actually advanced. Does nothing once the simulation has failed.
  double advance(double duration, double work_budget = 0.0, double piece = 0.0);

  // Sets live parameters (scene/parameters.h, live_parameter_keys()) from --set style text, all
  // at once: the cross-field rules are checked after the last one. `source` names where the values came from in errors.
  // Throws InputError for a key that is not live or a bad value, and then changes nothing.
  void set_parameters(const std::vector<std::pair<std::string, std::string>>& assignments, const std::string& source);
  // Takes the live fields of `edited` (the panel's copy of scene()).
  void set_live_parameters(const SceneSpec& edited);

  // The hand.
  bool is_held(std::uint32_t particle) const { return held_.contains(particle); }
  // Moves `particle` to `target` over `duration` s of simulated time (placed at once when
  // `duration` is 0 or the simulation is paused).
  void drag(std::uint32_t particle, const Vec3& target, double duration);
  // Lets go of a held particle (see the top of this file); nothing if it is not held.
  void release(std::uint32_t particle);
  // Pins a particle where it is (a held one stops being held); unpins frees it.
  void pin(std::uint32_t particle);
  void unpin(std::uint32_t particle);
  bool is_pinned(std::uint32_t particle) const;

  // The knife. Breaks the given connectors now (those still intact); returns how many broke.
  std::size_t cut(std::span<const std::uint32_t> connectors);
  // Breaks every intact connector that the segment between the rest-lattice points `from` and
  // `to` (row, col, in spacings; viewer/interaction.h) crosses; returns how many broke.
  std::size_t cut_in_lattice(const std::array<double, 2>& from, const std::array<double, 2>& to);

  // Break, yield and crease limits of every spring, live (Simulation::set_spring_limits); kept
  // across reset(). The caller checks them (check_spring_limits).
  void set_spring_limits(const SpringLimits& limits);
  const SpringLimits& spring_limits() const { return simulation_->model().limits; }

  // Obstacles (see the top of this file).
  bool self_collision() const { return simulation_->model().collision.self; }
  void set_self_collision(bool on);
  // Adds a sphere (centre in m, radius > 0 m) at rest; returns its index in the model's colliders.
  std::size_t add_sphere(const Vec3& center, double radius);
  // The model's sphere colliders, by index in model().colliders, in order (a script's "sphere"
  // numbers them from 0).
  std::vector<std::size_t> spheres() const;
  // Where the centre of sphere `collider` is now, m.
  Vec3 sphere_center(std::size_t collider) const;
  // Moves sphere `collider` in a straight line until its centre is at `target`, over `duration` s
  // of simulated time (placed at once when `duration` is 0 or the simulation is paused).
  void move_sphere(std::size_t collider, const Vec3& target, double duration);

  // Appends the current energies to the history, keeping `window` s of simulated time.
  void record_energy(double window = 10.0);
  const std::deque<EnergySample>& energy_history() const { return energy_history_; }

  // Particle index of lattice (row, col).
  std::uint32_t particle(int row, int col) const;

 private:
  void build();

  SceneSpec scene_;
  MemoryAllowance memory_;  // every build, resets included
  std::unique_ptr<Simulation> simulation_;
  bool playing_ = true;
  std::map<std::uint32_t, bool> held_;         // held particle -> whether it was pinned before the drag
  std::optional<SpringLimits> edited_limits_;  // set_spring_limits(), applied again after a reset
  std::optional<bool> edited_self_collision_;  // set_self_collision(), applied again after a reset
  std::vector<Collider> added_spheres_;        // add_sphere(), as added, added again after a reset
  std::deque<EnergySample> energy_history_;
};

// Why `limits` cannot be applied (a break strain below the yield strain, values out of range), or
// empty when they are valid: the panel's check before set_spring_limits().
std::string check_spring_limits(const SpringLimits& limits);

// Fires a script's events into a session. One call per displayed frame, frame numbers from 0.
class ScriptPlayer {
 public:
  ScriptPlayer(Script script, double frame_time);

  struct FrameRequests {
    std::vector<std::string> screenshots;  // PNG paths to write of this frame
    bool quit = false;
  };
  // Fires the events of `frame` in file order. Errors in "set" values were checked by
  // check_script(), so this does not throw for a checked script.
  FrameRequests fire(std::uint64_t frame, Session& session);
  // The last frame with an event; 0 for an empty script.
  std::uint64_t last_event_frame() const;

 private:
  Script script_;
  double frame_time_;
  std::vector<std::size_t> order_;  // event indices sorted by firing frame, file order within one
  std::size_t next_ = 0;            // first event in order_ not yet fired
};

}  // namespace clothsim::viewer
