// The Vulkan backend's integrator: RKF45, RK4 or symplectic Euler with the whole step on the
// device, so that no step waits for the host.
//
// The state, the model and the method's scratch live in device memory. An attempt at a step is
// a fixed sequence of passes, recorded once into a command buffer and submitted as often as
// needed (docs/gpu.md, "The step on the device"):
//   on a lattice:      lattice_stage         the three passes below in one, for up to three stages
//                                            a pass (float32; one in float64): each tile forms the
//                                            stage states its springs and its neighbours' reach, sums
//                                            their forces, K_i; the pass that ends the attempt forms
//                                            rk_solution's trial state and errors (per tile) as well,
//                                            and rk_solution does not run
//   or for each stage: rk_stage_state        y_i = y + h sum_j a_ij (V_j, K_j); anchors on their paths
//                      lattice_elements      each particle's own springs: their forces on it and on its
//                                            four neighbours, their damping power (a lattice sheet), or
//                      connector, radial     the element forces into slots (DeviceForces, any sheet)
//                      stage_acceleration    K_i: gathered force / mass, path accelerations; drag and anchor powers
//   rk_solution        the trial state and, for RKF45, each workgroup's largest scaled error
//   rk_control (0)     (without obstacles: first the work of the step accepted before, rk_control (1)'s)
//                      the largest error; accept or reject; the next step (PI controller), clipped to the target
//   rk_accept          on acceptance: state <- trial, and each workgroup's share of the step's work
//   rk_control (1)     with obstacles: the step's work added to the advance's sums (without, rk_control (3)
//                      adds the submission's last step's)
// With colliders, the obstacle pass between the decision and the acceptance (device_obstacles.cpp):
//   obstacle_contacts  each particle of the accepted trial state resolved against the colliders
//   obstacle_energy    the pass's energy change and contacts, and the next impact ahead, per workgroup
// and rk_control (1) then sets the next step, limited by that impact.
// A submission holds a batch of attempts; once the advance reaches its target (or fails, or has
// taken max_accepted steps) the remaining attempts of the batch return at once. After each
// submission the host reads back only the control arrays (a few hundred bytes), and after the
// last one the state. advance() runs to t_limit; step() stops after one accepted step.
//
// The host keeps a fingerprint of what it last exchanged with the device (the state as last read
// back or uploaded): a caller that changes the state between calls (a pinned particle) has it
// uploaded again, and a model whose revision moved (tearing by hand, parameter edits, anchors) is uploaded
// again. Anchor paths are written per advance relative to its start (device_step.h); a step never
// crosses an anchor event, which the Simulation guarantees by limiting each advance to the next.
//
// The results match the CPU's integrators within the precision's rounding and the tolerances,
// not bit for bit: the device adds the stage sums in the CPU's order, but the error norm's scale,
// the controller's factors (float, GLSL's pow) and the work sums (per workgroup) are its own.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "collision/obstacle_contacts.h"
#include "gpu/buffer.h"
#include "gpu/compute_pipeline.h"
#include "gpu/device.h"
#include "gpu/device_forces.h"
#include "gpu/pass_timer.h"
#include "gpu/shaders/device_step.h"
#include "gpu/state_checks.h"
#include "integrators/integrator.h"
#include "integrators/tableau.h"

namespace clothsim::gpu {

class DeviceIntegrator final : public Integrator {
 public:
  // Opens the device and uploads the model. `settings.kind` is rkf45, rk4 or symplectic_euler.
  // Throws GpuError, before allocating anything on the device, when there is no such device, it
  // lacks the precision, or the scene needs more memory than it has.
  DeviceIntegrator(const ClothModel& model, const IntegratorSettings& settings, const ForceOptions& options,
                   const DeviceSelection& selection);
  ~DeviceIntegrator() override;
  DeviceIntegrator(const DeviceIntegrator&) = delete;
  DeviceIntegrator& operator=(const DeviceIntegrator&) = delete;

  IntegratorKind kind() const override { return settings_.kind; }
  StepOutcome step(ClothState& state, double t_limit) override { return run(state, t_limit, 1); }
  StepOutcome advance(ClothState& state, double t_limit) override { return run(state, t_limit, 0); }
  // Host memory besides the state: the host's obstacle pass for the first step's limit (the
  // read-back staging is the driver's).
  std::size_t workspace_bytes() const override;
  // RKF45's next step and error history (the CPU's names, so checkpoints read the same).
  void transfer_state(StateArchive& archive) override;
  // Tearing, permanent stretching and creasing run on the device after every accepted step (the
  // lattice path; device_lattice.cpp); take_spring_events() carries the advance's changes into
  // the model.
  // With self-collision the laws act after the self pass, on the host between single steps.
  bool runs_spring_events() const override { return lattice_ && !model_.collision.self; }
  IntegratorEvents take_spring_events(ClothModel& model) override;
  // The model's obstacles (planes, spheres, boxes, capsules and triangle meshes, still or on their
  // paths) are resolved on the device after every accepted step, with the CPU's contact law, and
  // their impacts ahead limit the steps (device_obstacles.cpp); take_obstacle_contacts() gives an
  // advance's counts.
  bool runs_obstacle_contacts() const override { return collider_count_ > 0; }
  IntegratorContacts take_obstacle_contacts() override;
  // The frame's energies and checks on the device (gpu/state_checks.h), where it has
  // shaderFloat64 and the connectors' term is on (the stretch check reads their parameters);
  // nullopt elsewhere. A state changed by the caller since the last advance goes up first.
  std::optional<StateChecks> check_state(const ClothState& state, double explosion_stretch) override;

  const DeviceInfo& device_info() const { return device_.info(); }
  // True on the lattice path: each particle evaluates the springs it owns (lattice_elements);
  // false on the general path of element passes and force slots.
  bool lattice_path() const { return lattice_; }
  // Whether the lattice pass reads one particle's spring parameters for every particle: a sheet
  // whose springs of each kind are all alike and which no law changes (from the first advance on).
  bool reads_uniform_springs() const { return params_particle_ != kOwnParams; }
  // Device memory an attempt reads and writes per particle on the lattice path, bytes: each
  // array element a pass touches counted once (a neighbour's values as cached), summed over the
  // attempt's passes as last recorded (the event passes from the first advance on, where the
  // model's laws ask for them; docs/gpu.md, "Where the time goes"); 0 on the general path, not
  // counted.
  double traffic_per_particle_and_attempt() const;
  // "device traffic: ... bytes per particle and attempt", for `clothsim run --profile`.
  std::string profile_notes() const override;
  // The arrays DeviceForces holds: the general path's, or only what the lattice path reads.
  DeviceForcePath device_forces_path() const { return forces_.path(); }
  Precision precision() const { return precision_; }
  // Device memory the integrator holds for a model of these counts and anchors on force path
  // `path`, bytes: what is checked before allocating, and before a run builds its model
  // (sim/backend.h: a scene's model is a lattice, so the lattice path). The lattice path's own
  // arrays are counted on either path.
  // `colliders`: the model's obstacles, whose pass holds arrays per particle (their meshes' arrays,
  // read when the model is built, are checked then).
  // `chained_stages`: chained_stages_for's (0, three passes a stage, holds the most).
  static std::uint64_t device_bytes_for(const LatticeCounts& counts, std::size_t anchors, IntegratorKind kind,
                                        Precision precision, DeviceForcePath path = DeviceForcePath::lattice,
                                        std::size_t colliders = 0, std::uint32_t chained_stages = 0);
  // The stages lattice_stage chains in a pass on `device` for `passes` (unset: the device's
  // choice, DeviceSelection::stage_passes) on force path `path`; 0: three passes a stage.
  static std::uint32_t chained_stages_for(const Device& device, Precision precision, std::optional<StagePasses> passes,
                                          DeviceForcePath path);

  // The device's arrays besides DeviceForces' (which holds the stage state, the model and the
  // element scratch).
  enum Array : std::uint32_t {
    state_position,   // [3 particles], m
    state_velocity,   // [3 particles], m/s
    acceleration,     // [stages][3 particles], K_i, m/s^2
    rows,             // [stages + 2][kRowReals], the Nystrom rows
    control_real,     // [kControlReals]
    control_uint,     // [kControlUints]
    particle_anchor,  // [particles], int: anchor row or -1
    inverse_mass,     // [particles], 1/kg
    anchor_paths,     // [anchors][kPathReals]
    trial_position,   // [3 particles]
    trial_velocity,   // [3 particles]
    block_error,      // [solution workgroups]
    block_particle,   // [solution workgroups], uint
    particle_power,   // [3][particles], W: drag, anchor, damping (the lattice path), each weighed by the
                      // solution row and summed over the stages (shaders/device_step.h)
    block_work,       // [accept workgroups][3], J
    lattice_params,   // [particles][kLatticeParams] (the lattice path)
    lattice_forces,   // [particles][kLatticeForces] (the lattice path)
    event_params,     // [particles][kEventParams] (the lattice path's events)
    event_energy,     // [particles][2], J: fracture and plastic work of the step
    event_flags,      // [particles], uint: the connectors that broke in the step
    block_events,     // [workgroups][2], J
    colliders,        // [colliders][kColliderReals] (one row without colliders)
    contact_before,   // [particles][6]: a moved particle's state before the obstacle pass (one Real without colliders)
    moved,            // [particles], uint: 1 where the obstacle pass moved the particle (one word without)
    block_obstacles,  // [workgroups][kObstacleBlockReals] (one Real without colliders)
    mesh_reals,       // mesh colliders' vectors (device_step.h, kMeshHeaderUints; one Real without)
    mesh_uints,       // [colliders][kMeshHeaderUints], then mesh colliders' indices (one word without colliders)
    // float32: the state's low parts (shaders/split_state.glsl; one Real in float64). The trial
    // state's are DeviceForces' stage arrays, free from rk_solution to the next attempt's stages.
    state_position_low,
    state_velocity_low,
    array_count
  };

 private:
  // The control arrays as read back after a submission.
  struct Control {
    std::vector<double> reals;         // [kControlReals]
    std::vector<std::uint32_t> uints;  // [kControlUints]
  };

  // Sizes of the integrator's own arrays, bytes, for a model of these counts with `colliders`
  // obstacles (the obstacle arrays a placeholder each without; the meshes' arrays besides), its
  // stages run as `chained_stages` says (the three passes' arrays a placeholder where they chain).
  static std::array<std::uint64_t, array_count> array_bytes(const LatticeCounts& counts, int stages,
                                                            Precision precision, std::uint32_t anchor_capacity,
                                                            std::size_t colliders, std::uint32_t chained_stages);
  // Advances by accepted steps to t_limit, or by max_accepted of them (0: no limit).
  StepOutcome run(ClothState& state, double t_limit, std::uint32_t max_accepted);
  // Its stages: the first attempt's step (as the CPU's integrators choose it), the control arrays
  // written, the batches of attempts run, the state's time, anchors, work and the statistics.
  double first_step(const ClothState& state, double t_limit);
  // An advance's start, times relative to it: the first attempt's step, whether it ends on
  // step_limit (the target, or an impact ahead: `arrival`, +infinity for none).
  struct ControlStart {
    double step;
    bool clipped;
    double target;
    double step_limit;
    double arrival;
  };
  void write_control(const ControlStart& start, std::uint32_t max_accepted);
  Control run_attempts(std::uint32_t max_accepted);
  StepOutcome take_results(ClothState& state, double t0, double t_limit, const Control& control);
  // Uploads what changed on the host since the last exchange: the model, the state.
  void upload_changes(const ClothState& state);
  void write_anchor_paths(double t0);
  // A command buffer of a number of attempts, with the timestamps between its passes.
  struct RecordedAttempts {
    VkCommandBuffer commands = VK_NULL_HANDLE;
    std::unique_ptr<PassTimer> timer;
  };
  // The command buffer of `attempts` attempts, recorded on first use.
  RecordedAttempts& attempts_buffer(std::uint32_t attempts);
  // One attempt's passes, each run of them marked with its stage of the step (pass_timer.h).
  void record_attempt(VkCommandBuffer commands, PassTimer& timer) const;
  // lattice_stage's invocations: the lattice's tiles, a workgroup each.
  std::uint32_t lattice_stage_invocations() const;
  // rk_accept's invocations, and its workgroups: the blocks of work that rk_control's phases 1 and
  // 3 add.
  std::uint32_t rk_accept_items() const;
  std::uint32_t rk_accept_blocks() const;
  // Drops the recorded command buffers, to be recorded again (the passes or their arrays changed).
  void release_recorded();
  // Binds every pass's arrays (again after the anchor table grows).
  void bind_passes();
  void read_state(ClothState& state);
  // `bytes` into `destination` through input_staging_, grown to hold them: what goes up each advance.
  void upload_input(Buffer& destination, std::span<const std::byte> bytes);
  // The lattice path (device_lattice.cpp): the per-particle spring parameters and the events'
  // thresholds from the model, and whether the sheet is uniform (params_particle_); which laws act
  // (laws_, from the model's limits); the events of an advance applied to the model through
  // model/model_edits.h.
  void upload_lattice_params();
  std::uint32_t uniform_params_particle(const std::vector<double>& params, const std::vector<double>& events) const;
  void set_laws();
  // The obstacles (device_obstacles.cpp): their arrays sized for the model's colliders and their
  // meshes uploaded (again when their number changed), their rows written for an advance from t0,
  // the first step's limit (the CPU's ObstacleContacts::begin_step on the state the advance starts
  // from, +infinity without colliders), their passes recorded into an attempt.
  void prepare_obstacles();
  void upload_colliders(double t0);
  double first_arrival(const ClothState& state);
  void record_obstacle_passes(VkCommandBuffer commands, PassTimer& timer) const;

  const ClothModel& model_;
  IntegratorSettings settings_;
  ForceOptions options_;
  ButcherTableau tableau_;
  bool adaptive_;
  bool symplectic_;
  bool lattice_;
  // On the lattice path, the stages lattice_stage chains in a pass (DeviceSelection::stage_passes);
  // 0: three passes a stage.
  std::uint32_t chained_stages_ = 0;
  std::uint32_t laws_ = 0;  // EventPassConstants::laws of the recorded attempts
  // LatticePassConstants::params_particle of the recorded attempts (device_lattice.cpp).
  std::uint32_t params_particle_ = kOwnParams;
  // The colliders the obstacle arrays are sized for; the recorded attempts run the obstacle passes
  // when there are any.
  std::size_t collider_count_ = 0;
  ObstacleContacts first_arrival_;  // the host's pass, for the first step's limit only
  IntegratorContacts contacts_;     // since the last take_obstacle_contacts()
  IntegratorEvents events_;         // since the last take_spring_events()
  double events_t0_ = 0.0;          // the start of the advance whose events wait for take_spring_events()
  Precision precision_;
  Device device_;
  DeviceForces forces_;
  std::uint32_t particles_, elements_, anchor_capacity_;
  std::vector<Buffer> arrays_;  // [array_count]
  Buffer control_real_readback_, control_uint_readback_;
  Buffer state_staging_;  // the state both ways (gpu/state_transfer.h)
  // What goes up each advance (the control words, the anchor paths, the collider rows), through
  // one staging buffer that grows as needed: upload_input().
  Buffer input_staging_;
  ComputePipeline stage_state_pass_, lattice_pass_, acceleration_pass_, lattice_stage_pass_, solution_pass_,
      control_pass_, events_connectors_pass_, events_radial_pass_, accept_pass_, obstacle_contacts_pass_,
      obstacle_energy_pass_;
  std::map<std::uint32_t, RecordedAttempts> recorded_;  // by attempts per submission
  std::optional<StateChecksPass> state_checks_;         // where check_state() runs on the device

  // What the host last exchanged with the device: a fingerprint of the state (not a copy of it).
  bool exchanged_ = false;
  std::uint64_t exchanged_fingerprint_ = 0;
  std::uint64_t model_revision_ = 0;
  // The controller between advances (the device holds it during one).
  double proposed_step_ = 0.0;
  double previous_error_ = 1e-4;
  std::uint32_t expected_attempts_ = 4;  // attempts the last advance took
};

}  // namespace clothsim::gpu
