// One interface for every time integrator.
//
// An integrator advances a ClothState by one accepted step at a time, never past a limit given by
// the caller (the next frame time), so that steps land exactly on frame times and discrete events
// (tearing, plasticity, collisions) run between steps, never inside the stages of one.
// Integrators own their scratch memory (allocated in the constructor): step() does not allocate.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/record_fields.h"
#include "core/state_archive.h"
#include "core/step_profile.h"
#include "forces/forces.h"
#include "model/cloth_model.h"
#include "model/surface_contacts.h"

namespace clothsim {

enum class IntegratorKind : std::uint8_t { rkf45, rk4, symplectic_euler, implicit_euler, imex };

std::string_view to_string(IntegratorKind kind);
// Every kind, in enum order: the values to_string() names (so a new kind appears here, in the
// benchmark suite for instance, as soon as to_string() knows it).
std::vector<IntegratorKind> all_integrator_kinds();
// Parses "rkf45", "rk4", "symplectic-euler", "implicit-euler", "imex"; returns false for anything else.
bool parse_integrator_kind(std::string_view text, IntegratorKind& kind);

// The step of the explicit fixed-step methods and RKF45's and imex's first trial step where a scene
// sets none (scene_integrator() in scene/scene.h; implicit Euler's is the frame step).
inline constexpr double kDefaultTimeStep = 1e-3;  // s

struct IntegratorSettings {
  IntegratorKind kind = IntegratorKind::rkf45;
  // RKF45 and imex error control: a step is accepted when every free coordinate's error estimate e_i
  // satisfies |e_i| <= absolute_tolerance + relative_tolerance * |y_i| (max norm).
  double relative_tolerance = 1e-6;  // dimensionless
  double absolute_tolerance = 1e-6;  // m for positions, m/s for velocities
  // Fixed-step methods: the step. RKF45, imex: the first trial step (0 picks one automatically).
  double time_step = kDefaultTimeStep;  // s
  double min_step = 1e-10;              // s; RKF45 and imex stop with a diagnosis if they need a smaller step
  double max_step = 0.1;                // s; upper bound on RKF45 and imex steps
  // Step-size controller (Hairer, Norsett and Wanner, Solving ODEs I, sec. II.4).
  double safety = 0.9;      // factor on the optimal step
  double max_growth = 5.0;  // largest step increase per step
  double max_shrink = 0.1;  // smallest step decrease factor after a rejection
  // Implicit Euler's linear solve (conjugate gradients): stop when the residual's norm is below
  // cg_tolerance times the right-hand side's, or after cg_max_iterations. (imex's stage solves
  // derive their target from absolute_tolerance instead, integrators/imex.h; the cap applies.)
  double cg_tolerance = 1e-3;  // dimensionless
  int cg_max_iterations = 2000;
  // Adds a coarse-grid correction to the Jacobi preconditioner: the system restricted to
  // aggregates of 4 x 4 particles, solved exactly (two-level additive preconditioner).
  bool cg_two_level = true;
  // With cg_two_level: the coarse-grid correction is a multigrid V-cycle (bilinear interpolation,
  // Galerkin coarse matrices down to 8 x 8 nodes, Gauss-Seidel smoothing; integrators/multigrid.h)
  // instead of the exact solve on 4 x 4 aggregates.
  bool cg_multigrid = true;
  // With cg_multigrid: the V-cycle's fine-level smoother solves whole lattice rows and columns
  // (block line Gauss-Seidel) instead of one particle at a time; integrators/multigrid.h, and on
  // the vulkan backend gpu/device_multigrid.h.
  bool cg_line_smoother = true;
  // With cg_multigrid: the V-cycle is set up for a solve only where block Jacobi alone would take
  // more than this many iterations by BlockSystem::jacobi_iterations_estimate(); below, Jacobi
  // is cheaper than the V-cycle's setup and passes (0: the V-cycle always). Not a scene key: the
  // library's tests force the V-cycle with it.
  double cg_vcycle_threshold = 80.0;
  // The blow-up check (sim/simulation.h): a run whose energy balance gains more than this fraction
  // of its energy scale stops as failed.
  double energy_error_limit = 10.0;  // dimensionless
};

// Counters for one run, reported in summary.json's "integrator".
struct IntegratorStats {
  std::uint64_t accepted_steps = 0;
  std::uint64_t rejected_steps = 0;
  std::uint64_t force_evaluations = 0;
  double smallest_step = std::numeric_limits<double>::infinity();  // s, accepted steps only
  double largest_step = 0.0;                                       // s, accepted steps only
  double last_step = 0.0;                                          // s
  // Implicit Euler and imex: conjugate-gradient iterations, in all steps and the most in one step, and
  // the solves that stopped at cg_max_iterations before reaching cg_tolerance.
  std::uint64_t cg_iterations = 0;
  std::uint64_t cg_max_iterations_in_a_step = 0;
  std::uint64_t cg_unconverged_solves = 0;

  // Every field, in order, with how it adds up over a run's integrators (core/record_fields.h).
  template <typename Self, typename Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit("accepted_steps", self.accepted_steps, Tally::sum);
    visit("rejected_steps", self.rejected_steps, Tally::sum);
    visit("force_evaluations", self.force_evaluations, Tally::sum);
    visit("smallest_step", self.smallest_step, Tally::least);
    visit("largest_step", self.largest_step, Tally::greatest);
    visit("last_step", self.last_step, Tally::latest);
    visit("cg_iterations", self.cg_iterations, Tally::sum);
    visit("cg_max_iterations_in_a_step", self.cg_max_iterations_in_a_step, Tally::greatest);
    visit("cg_unconverged_solves", self.cg_unconverged_solves, Tally::sum);
  }
};

// The statistics of a run whose integrator was replaced: `earlier`'s (the replaced integrators')
// and `later`'s (the current one's), field by field as their Tally says.
IntegratorStats combine(const IntegratorStats& earlier, const IntegratorStats& later);

enum class StepStatus : std::uint8_t {
  ok,
  step_underflow,  // the error control asked for a step below min_step
  non_finite,      // a fixed-step method produced NaN or infinity
};

struct StepOutcome {
  StepStatus status = StepStatus::ok;
  double step = 0.0;  // s, the step taken (or the one refused)
  // The particle with the largest error (step_underflow) or the first non-finite value.
  std::uint32_t particle = 0;
  bool non_finite_error = false;  // step_underflow caused by non-finite stage values
};

// Tearing, permanent stretching and creasing applied by an integrator that runs the laws itself,
// between its own steps (gpu/device_integrator.h), instead of the Simulation's event stage.
struct IntegratorEvents {
  std::size_t breaks = 0;
  std::size_t yields = 0;
  std::size_t creases = 0;
};

// Obstacle contacts resolved by an integrator that runs the collision stage's obstacle pass
// itself, between its own steps (gpu/device_integrator.h), over one advance.
struct IntegratorContacts {
  std::size_t last = 0;     // particles the pass moved in the advance's last step
  std::uint64_t steps = 0;  // the same, summed over the advance's steps
  std::size_t most = 0;     // the most in one of its steps
};

// Self-collision resolved by an integrator that runs the collision stage's self pass itself, between
// its own steps (gpu/device_implicit_euler.h), over one advance; in pairs of elements, as
// ContactStatistics counts them.
struct IntegratorSelfContacts {
  std::size_t last = 0;          // pairs pushed apart after the advance's last step
  std::uint64_t steps = 0;       // the same, summed over the advance's steps
  std::size_t most = 0;          // the most in one of its steps
  std::uint64_t impacts = 0;     // responses to pairs whose motion touched
  std::uint64_t zones = 0;       // impact zones moved as one
  std::uint64_t unresolved = 0;  // pairs left touching after the zones (0 expected)
};

// What the Simulation checks after an advance, computed by an integrator whose state lives on a
// device (Integrator::check_state).
struct StateChecks {
  EnergyReport energy;  // compute_energy's terms of the state, for the model's force terms
  bool failed = false;  // a non-finite position or velocity, or a live connector stretched too far
};

struct ForceOptions {
  ForceTerms terms = kAllForceTerms;
  int threads = 1;  // resolved thread count (>= 1)
  ForceKernel kernel = ForceKernel::automatic;
  // The arithmetic of the springs: float32 is the lattice kernel's (forces/lattice_kernel.h),
  // for the explicit methods; the state and the integration stay float64 either way.
  Precision precision = Precision::float64;
  // The lattice kernel's scratch in both precisions, for `precision: auto`'s choice frame by frame
  // (sim/precision_choice.h; ForceBuffers::both_precisions).
  bool both_precisions = false;
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  virtual IntegratorKind kind() const = 0;
  // Advances `state` by one accepted step ending at or before t_limit (> state.time). The model
  // must be the one the integrator was made for.
  virtual StepOutcome step(ClothState& state, double t_limit) = 0;
  // Advances `state` toward t_limit (> state.time) by accepted steps: by one (the default,
  // step()), or, for an integrator whose state lives on a device (gpu/device_integrator.h), by as
  // many as reach t_limit without the host between steps. The Simulation calls it where nothing
  // runs between steps that the integrator does not run itself.
  virtual StepOutcome advance(ClothState& state, double t_limit) { return step(state, t_limit); }
  const IntegratorStats& stats() const { return stats_; }
  // Wall time in the stages it times (core/step_profile.h): forces, and the parts of integration
  // it has (stage sums, solution and error, ...); the Simulation times the step as a whole.
  const StepProfile& profile() const { return profile_; }
  // Bytes of scratch memory the integrator holds: stage arrays, force buffers, and so on.
  virtual std::size_t workspace_bytes() const { return 0; }
  // Lines that `clothsim run --profile` prints under the profile's table (the device's memory
  // traffic per attempt); none by default.
  virtual std::string profile_notes() const { return {}; }
  // True when the integrator applies tearing, permanent stretching and creasing itself after each
  // of its steps (events/spring_events.h's laws, on a device: gpu/device_integrator.h). The
  // Simulation then calls take_spring_events() after each advance() instead of running its event
  // stage: the integrator makes its changes in `model` (the one it was made for, through
  // model/model_edits.h) and returns their counts; the work they released is in the state already.
  virtual bool runs_spring_events() const { return false; }
  virtual IntegratorEvents take_spring_events(ClothModel& /*model*/) { return {}; }
  // True when the integrator resolves the model's obstacles itself after each of its steps (the
  // collision stage's obstacle pass, collision/obstacle_contacts.h, on a device) and limits its
  // steps by their impacts ahead. The Simulation then neither limits the advance nor runs its
  // collision stage, and calls take_obstacle_contacts() after each advance() for the counts; the
  // contact work is in the state already.
  virtual bool runs_obstacle_contacts() const { return false; }
  virtual IntegratorContacts take_obstacle_contacts() { return {}; }
  // True when the integrator also runs the collision stage's self pass (collision/self_contacts.h)
  // after each of its steps, after its obstacle pass (so only an integrator that runs the obstacles
  // runs it, where there are any). The Simulation then runs no collision stage at all and calls
  // take_self_contacts() after each advance() for the counts; the contact work is in the state.
  virtual bool runs_self_contacts() const { return false; }
  virtual IntegratorSelfContacts take_self_contacts() { return {}; }
  // The energies of `state` and the Simulation's checks of it (Simulation::check_state: a
  // non-finite value; a live connector longer than `explosion_stretch` times its rest length),
  // computed where the integrator keeps the state: a device integrator sums them there, and the
  // host reads its partial sums instead of summing a large sheet's springs each frame
  // (gpu/state_checks.h). `state` is the caller's, as after the last advance or changed since.
  // Nullopt (the default) where the integrator does not compute them: the Simulation does. A
  // failure found here is diagnosed by the Simulation's own check, which names the element.
  virtual std::optional<StateChecks> check_state(const ClothState& /*state*/, double /*explosion_stretch*/) {
    return std::nullopt;
  }
  // `precision: auto` on the CPU, frame by frame (sim/precision_choice.h). The largest difference
  // over the particles between the accelerations that float32 and float64 forces give at `state`
  // (m/s^2; two force evaluations, counted as the integrator's), where the integrator can run
  // float32 forces (the explicit methods, on the lattice kernel); nullopt (the default) elsewhere.
  virtual std::optional<double> float32_acceleration_error(const ClothState& /*state*/) { return std::nullopt; }
  // The precision of the forces from the next step on, where float32_acceleration_error() has a
  // value; nothing elsewhere.
  virtual void set_force_precision(Precision /*precision*/) {}
  // The particles resting on obstacles, which the collision stage refreshes before each step: an
  // integrator that can hold them on their surface within a step reads them and writes the
  // impulses it needed (model/surface_contacts.h). Null (the default): none.
  void set_surface_contacts(SurfaceContacts* contacts) { surface_contacts_ = contacts; }
  // Saves or restores what the next step depends on besides the state and the model, so that a
  // restored integrator takes the steps the saved one would have (checkpoints, io/checkpoint.h):
  // the statistics, and in the derived classes their controller state (RKF45's next step and
  // error history, implicit Euler's warm start). Scratch that every step recomputes is not saved.
  // Restoring requires an integrator of the same kind, made for the same model.
  virtual void transfer_state(StateArchive& archive);

 protected:
  // Counts an accepted step of size h (s) in stats_.
  void record_accepted_step(double h) {
    ++stats_.accepted_steps;
    stats_.smallest_step = std::min(stats_.smallest_step, h);
    stats_.largest_step = std::max(stats_.largest_step, h);
    stats_.last_step = h;
  }

  // Adds to stats_.force_evaluations what a counter of the integrator's own (ClothDynamics::
  // evaluations(), which starts at 0 with the integrator) has counted since the last call, so that
  // a count restored from a checkpoint goes on from where it was.
  void count_evaluations(std::uint64_t total) {
    stats_.force_evaluations += total - evaluations_counted_;
    evaluations_counted_ = total;
  }

  IntegratorStats stats_;
  std::uint64_t evaluations_counted_ = 0;
  StepProfile profile_;
  SurfaceContacts* surface_contacts_ = nullptr;
};

std::unique_ptr<Integrator> make_integrator(const ClothModel& model, const IntegratorSettings& settings,
                                            const ForceOptions& force_options);

}  // namespace clothsim
