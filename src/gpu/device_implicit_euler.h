// Implicit Euler on the Vulkan backend: the CPU's method (integrators/implicit_euler.h, one
// Newton step of backward Euler, Baraff and Witkin 1998) with the state, the linearisation and the
// conjugate gradients on the device. Per step, as named stages (docs/gpu.md, "Implicit Euler on
// the device"):
//   forces             f0 = f(x0, v0), the element passes and the gather of gpu/device_forces.h
//                      (reused from the last step's end when the state is that one)
//   implicit_linearize each element's Jacobian factors at (x0, v0) (forces/element_jacobian.inc,
//                      the CPU's text)
//   implicit_setup     z (h v, or an anchor's path displacement), anchors' known dv
//   implicit_product, implicit_gather   b = h (f0 - K z)
//   implicit_diagonal  the block Jacobi preconditioner: each particle's diagonal block, inverted
//   multigrid_*        with the V-cycle: level 0's matrix, the coarse levels, the coarsest factor
//   the solve          r = b - A u from the last step's dv, then iterations of
//                      q = A p (implicit_product + implicit_gather), alpha (implicit_reduce),
//                      u, r, z (implicit_iterate; with the V-cycle, z from it), beta (implicit_reduce),
//                      p (implicit_iterate)
//   implicit_setup     the check for a non-finite dv; v += dv, x += h v; anchors on their paths
//   forces             f(x1, v1), and the step's end powers for the work integrals
// The matrix A = M + h (C + drag) + h^2 K is never assembled: its products are matrix-free from the
// element factors, each particle's row summed in the gather table's order. The reductions add per
// workgroup and then over the workgroups in a fixed order: the same bits on every run on a device.
//
// The host drives the steps: it writes a step's scalars and anchor rows into host-visible staging,
// which the step's first submission copies in, submits the step's passes with a first batch of
// iterations, reads the solve's progress (a few words each submission copies back) and submits
// more iterations until it stops, then the step's end. The state stays on the device; it comes
// back when an advance ends.
//
// Obstacles (device_implicit_obstacles.cpp): the collision stage's obstacle pass runs on the device
// after every step, as the explicit methods' does (gpu/device_integrator.h), with the CPU's contact
// law, and leaves the next step its surface contacts (model/surface_contacts.h) and its limit, the
// earliest impact ahead:
//   obstacle_contacts         each free particle resolved against the colliders; friction on the
//                             impulse of the surface it was held on
//   obstacle_energy_elements  the energy the pass changed, the held particles' surface impulses'
//                             work, the particles moved; the particles resting on a surface and the
//                             earliest arrival of the others, for the next step
//   implicit_reduce           their sums, which the host reads with the step's counters
// The device holds the particles resting on a surface as the CPU does (implicit_diagonal: along
// the normal or in all directions, the held directions filtered out of the solve) and lets go of
// those the surface would pull and solves again. So the host has nothing to do between steps with
// obstacles alone.
//
// Self-collision (device_implicit_self.cpp): the collision stage's self pass on the device after the
// obstacle pass (gpu/device_self_contacts.h), which enters the particles it moves in the obstacle
// pass's ledger so that the booking after both books both passes' work; where the device's rounds
// leave pairs touching, the host's pass finishes that step on the state read back (the zones).
//
// Tearing, permanent stretching and creasing (device_implicit_events.cpp): after the obstacle pass,
//   implicit_events    the CPU's laws (events/spring_laws.inc) per connector, then per radial spring,
//                      on DeviceForces' element arrays, which the next step's forces read
//   implicit_reduce    the fracture and plastic work
// and take_spring_events() carries an advance's changes into the host's model.
//
// The preconditioner is the CPU's: on a lattice with cg_two_level and cg_multigrid (the defaults),
// the multigrid V-cycle (gpu/device_multigrid.h) where block Jacobi would take more than
// cg_vcycle_threshold iterations by the CPU's estimate, read from the device after the passes
// before the solve; block Jacobi else, and on a model that is not a lattice or with cg_two_level
// false (the CPU's two-level aggregates without the multigrid are not on the device: block Jacobi
// there too). The results match the CPU's within the solve's tolerance, not bit for bit: the
// matrix-free products round differently from assembled blocks, and the V-cycle's sweeps visit
// the nodes in 9 colours where the CPU's go in bands of rows.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

#include "collision/self_contacts.h"
#include "gpu/buffer.h"
#include "gpu/compute_pipeline.h"
#include "gpu/device.h"
#include "gpu/device_forces.h"
#include "gpu/device_multigrid.h"
#include "gpu/device_self_contacts.h"
#include "gpu/pass_timer.h"
#include "gpu/shaders/implicit_step.h"
#include "gpu/state_checks.h"
#include "integrators/integrator.h"

namespace clothsim::gpu {

class DeviceImplicitEuler final : public Integrator {
 public:
  // Opens the device and uploads the model. Throws GpuError, before allocating anything on the
  // device, when there is no such device, it lacks the precision, or the scene needs more memory
  // than it has.
  DeviceImplicitEuler(const ClothModel& model, const IntegratorSettings& settings, const ForceOptions& options,
                      const DeviceSelection& selection);
  ~DeviceImplicitEuler() override;
  DeviceImplicitEuler(const DeviceImplicitEuler&) = delete;
  DeviceImplicitEuler& operator=(const DeviceImplicitEuler&) = delete;

  IntegratorKind kind() const override { return IntegratorKind::implicit_euler; }
  StepOutcome step(ClothState& state, double t_limit) override { return run(state, t_limit, 1); }
  StepOutcome advance(ClothState& state, double t_limit) override { return run(state, t_limit, 0); }
  // The warm start of the next solve (the last step's dv) and the statistics, by the CPU's names.
  void transfer_state(StateArchive& archive) override;
  // The frame's energies and checks on the device (gpu/state_checks.h, the general path's pass),
  // where it has shaderFloat64 and the connectors' term is on; nullopt elsewhere.
  std::optional<StateChecks> check_state(const ClothState& state, double explosion_stretch) override;

  const DeviceInfo& device_info() const { return device_.info(); }
  // CG iterations of the last step.
  int last_iterations() const { return last_iterations_; }
  // The model's obstacles, resolved on the device after each step (device_implicit_obstacles.cpp);
  // take_obstacle_contacts() gives the counts since the last call.
  bool runs_obstacle_contacts() const override { return !model_.colliders.empty(); }
  IntegratorContacts take_obstacle_contacts() override;
  // Self-collision, on the device after the obstacle pass (gpu/device_self_contacts.h), the host's
  // pass finishing a step where the device's leaves pairs touching (device_implicit_self.cpp).
  bool runs_self_contacts() const override { return model_.collision.self; }
  IntegratorSelfContacts take_self_contacts() override;
  // The model's laws (tearing, permanent stretching, creasing), applied on the device after each
  // step and its collision passes (device_implicit_events.cpp), where every spring term is on
  // (DeviceForces' flags of a spring whose term is off say absent, not broken);
  // take_spring_events() carries the changes into the model.
  bool runs_spring_events() const override;
  IntegratorEvents take_spring_events(ClothModel& model) override;

  // Device memory for a model of these counts, bytes: DeviceForces' general path and the arrays below.
  // `colliders`: the model's obstacles (the obstacle pass's arrays; their meshes' are besides); the
  // V-cycle's levels where DeviceMultigrid::applies(counts, settings); with `self_collision`, the
  // self pass's arrays (DeviceSelfContacts::bytes_for) and the obstacle pass's, which it books in.
  static std::uint64_t device_bytes_for(const LatticeCounts& counts, std::size_t anchors, Precision precision,
                                        std::size_t colliders, const IntegratorSettings& settings, bool self_collision);
  // The workgroups of the obstacle pass's three phases (obstacle_energy_elements), in block_sums.
  static std::uint64_t obstacle_blocks(std::uint64_t particles, std::uint64_t connectors, std::uint64_t radials);
  // Whether the last step's solve took the V-cycle.
  bool last_solve_took_vcycle() const { return vcycle_; }
  // The iterations recorded into the step's first submission, and into each further one.
  static constexpr std::uint32_t kFirstIterations = 8;
  static constexpr std::uint32_t kMoreIterations = 32;

  enum Array : std::uint32_t {
    connector_factors,  // [connectors][kConnectorFactorReals]
    radial_factors,     // [radials][kRadialFactorReals]
    particle_anchor,    // [particles], int: anchor row or -1
    solution,           // [3 particles], dv, m/s (the warm start between steps)
    rhs,                // [3 particles], b, N s
    residual,           // [3 particles]
    preconditioned,     // [3 particles], z = P^-1 r
    direction,          // [3 particles], p (and the vector implicit_product multiplies)
    product,            // [3 particles], q = A p
    jacobi,             // [particles][9], the inverse diagonal blocks
    block_sums,         // [workgroups][3], partial sums
    solve_real,         // [kSolveReals] (implicit_step.h)
    solve_uint,         // [kSolveUints]
    anchor_rows,        // [anchor capacity][kAnchorRowReals]
    hold,               // [particles], uint: kHold*
    slipped,            // [particles], uint: 1 where held stuck by more than friction in the last step
    // With colliders (a placeholder each without): the obstacle pass's arrays.
    surface_contacts,  // [particles][kContactReals]: the surface each particle rests on at the step's start
    impulse,           // [3 particles], N s: the surface impulses of the held particles
    start_position,    // [3 particles], m: the step's start, from which the pass sweeps
    contact_before,    // [particles][6]: a moved particle's state before the pass
    moved,             // [particles], uint: 1 where the pass moved the particle
    colliders,         // [colliders][kColliderReals] (device_step.h)
    mesh_reals,        // the mesh colliders' arrays (gpu/device_colliders.h)
    mesh_uints,
    obstacle_control_real,  // [kControlReals]: the pass's times and thickness at device_step.h's slots
    obstacle_control_uint,  // [kControlUints]: kAccepted, 1
    // With the laws (a placeholder each without): their per-spring values.
    connector_events,    // [connectors][kEventsPerConnector] (implicit_step.h)
    radial_arms,         // [radials][2], uint: the connectors of its two arms
    radial_yield_angle,  // [radials], rad
    connector_broke,     // [connectors], uint: 1 where it broke after the last step
    array_count
  };

 private:
  // Each array's bytes; `colliders`: the model's obstacles, whose pass holds arrays per particle
  // and partial results per workgroup of its three phases (placeholders without obstacles and
  // without self-collision, whose pass the obstacle pass's arrays serve too; the meshes' arrays
  // are besides).
  static std::array<std::uint64_t, array_count> array_bytes(const LatticeCounts& counts, Precision precision,
                                                            std::uint32_t anchor_capacity, std::size_t colliders,
                                                            bool self_collision);
  // Steps to t_limit, or max_steps of them (0: no limit), as named stages.
  StepOutcome run(ClothState& state, double t_limit, std::uint32_t max_steps);
  // One step of h ending at end_time: its scalars and anchor rows written, the passes before the
  // solve, the solve, the update and the end's forces and powers. Returns the first free particle
  // whose dv is not finite, or kNoParticle (the state is then unchanged).
  std::uint32_t take_step(double h, double end_time);
  void write_step(double h, double end_time);
  void write_solve_counters();
  // The solve's counters and scalars as the last submission copied them back.
  std::uint32_t output_uint(std::uint32_t slot) const;
  double output_real(std::uint32_t slot) const;
  // Submits iterations until the solve stops; returns its iterations.
  int solve(VkCommandBuffer first);
  // Whether this step's solve takes the V-cycle, from the stiffness ratio the passes before it read.
  bool choose_vcycle() const;
  // The obstacles (device_implicit_obstacles.cpp): the arrays sized for the model's colliders when
  // their number changed, or when self-collision was switched, whose pass uses them too (true: the
  // passes are then to be bound and recorded anew); at an advance's start from t0, the colliders'
  // rows and the surface contacts and first limit of the state there; after a step from tau0 to
  // tau1 (s from t0), the pass, then the self pass where it runs, their work booked in `state`
  // and their counts kept.
  bool prepare_obstacles();
  void begin_obstacles(double t0);
  void resolve_obstacles(ClothState& state, double tau0, double tau1);
  // Self-collision (device_implicit_self.cpp): at an advance's start, the pass made for the sheet
  // as it is and its candidates forgotten; after a step's obstacle pass, the device's pass with the
  // obstacle pass's ledger; where it leaves pairs touching, after the booking, the host's self pass
  // on the state read back, which finishes it with the impact zones and books its own work.
  void begin_self_contacts();
  std::size_t resolve_self_contacts(double h);
  void finish_self_contacts_on_host(ClothState& state, double h);
  // The obstacle pass's results the last submission copied back: the resting flag for the next
  // step's holds and the step limit it sets.
  void read_obstacle_outputs(double time);
  void write_obstacle_control(double tau0, double tau1);
  void bind_obstacle_passes();
  void record_obstacle_buffers();
  void record_obstacle_reduction(VkCommandBuffer commands, std::uint32_t blocks) const;
  // The laws (device_implicit_events.cpp): which act (kLaw* bits); the per-spring values uploaded
  // from the model; the passes after a step, and their work booked and counts kept.
  std::uint32_t laws() const;
  // Whether the laws' passes are recorded: some law acts and every spring term is on (whether they
  // run also depends on self-collision, which the viewer switches between frames).
  bool records_spring_events() const;
  void upload_events();
  void apply_spring_events(ClothState& state);
  void bind_event_passes();
  void record_event_buffers();
  // Uploads what changed on the host since the last exchange: the model, the state
  // (device_implicit_state.cpp).
  void upload_changes(const ClothState& state);
  void read_state(ClothState& state);
  void bind_passes();
  // Command buffers recorded once: the forces at the current state; the passes before the solve;
  // for each preconditioner, the first residual with a first batch of iterations, and a batch of
  // iterations; the step's end.
  void record_buffers();
  void release_buffers();
  // A command buffer recorded by `record`, which marks at most `marks` runs of passes on the
  // timer it is given; submit() runs it and adds its device time per part to the profile.
  VkCommandBuffer record_timed(std::uint32_t marks, const std::function<void(VkCommandBuffer, PassTimer&)>& record);
  void submit(VkCommandBuffer commands);
  // `vcycle`: z from the V-cycle, else from block Jacobi.
  void record_iterations(VkCommandBuffer commands, bool vcycle, std::uint32_t iterations) const;
  // Both solve arrays copied back, for output_uint() and output_real() after the submission.
  void record_solve_readback(VkCommandBuffer commands) const;
  // Records `pass` in `phase` over `invocations`; `iteration`: a CG iteration's pass, which returns
  // at once once the solve has stopped.
  void dispatch(VkCommandBuffer commands, const ComputePipeline& pass, std::uint32_t phase, std::uint32_t invocations,
                bool iteration = false) const;
  // direction = dv, and the element part of A dv into the force slots; the first residual from
  // there (the warm start) and the start's sums; the held particles' surface impulses A dv - b.
  void record_solution_product(VkCommandBuffer commands) const;
  void record_first_residual(VkCommandBuffer commands, bool vcycle) const;
  void record_surface_impulses(VkCommandBuffer commands) const;
  std::uint32_t workgroups() const;
  ImplicitPassConstants constants(std::uint32_t phase) const;

  const ClothModel& model_;
  IntegratorSettings settings_;
  ForceOptions options_;
  Precision precision_;
  Device device_;
  DeviceForces forces_;
  std::optional<StateChecksPass> state_checks_;  // where check_state() runs on the device
  std::uint32_t particles_, connectors_, radials_;
  std::vector<Buffer> arrays_;  // [array_count]
  std::uint32_t anchor_capacity_;
  // Host-visible: what the host writes for a step, what the submissions copy back, and the state
  // both ways (gpu/state_transfer.h).
  Buffer real_input_, uint_input_, anchor_input_, real_output_, uint_output_, state_staging_;
  ComputePipeline linearize_pass_, product_pass_, gather_pass_, diagonal_pass_, reduce_pass_, iterate_pass_,
      setup_pass_, obstacle_contacts_pass_, obstacle_elements_pass_, events_pass_;
  std::optional<DeviceMultigrid> multigrid_;  // on a lattice with the CPU's multigrid settings
  bool vcycle_ = false;                       // this step's solve takes the V-cycle
  VkCommandBuffer forces_commands_ = VK_NULL_HANDLE, prepare_commands_ = VK_NULL_HANDLE, end_commands_ = VK_NULL_HANDLE;
  // Per preconditioner (block Jacobi, the V-cycle): the first residual and iterations; more
  // iterations; with held particles, the solve again after a release, from where it stopped.
  std::array<VkCommandBuffer, 2> first_commands_{}, iteration_commands_{}, restart_commands_{};
  // With held particles: the surface impulses and the release of those a surface would pull; the
  // final impulses, copied back.
  VkCommandBuffer release_commands_ = VK_NULL_HANDLE, impulse_commands_ = VK_NULL_HANDLE;
  // Each recorded buffer's timestamps (gpu/pass_timer.h).
  std::unordered_map<VkCommandBuffer, std::unique_ptr<PassTimer>> timers_;
  // With colliders: the surface contacts and the first limit at an advance's start; the pass after
  // a step. Host-visible: the pass's control reals, written before each.
  // The pass's resolution and its booking are two buffers, with the self pass between them.
  VkCommandBuffer contacts_commands_ = VK_NULL_HANDLE, obstacle_commands_ = VK_NULL_HANDLE,
                  booking_commands_ = VK_NULL_HANDLE;
  bool obstacle_pass_ = false;  // its arrays are sized and it runs (colliders, or self-collision)
  Buffer obstacle_input_, colliders_input_;
  std::size_t collider_count_ = 0;  // the colliders the obstacle arrays are sized for
  IntegratorContacts contacts_;     // since the last take_obstacle_contacts()
  double step_limit_ = 0.0;         // s: the next step may not end after it (+infinity: no limit)
  bool holding_ = false;            // the next step holds the particles resting on a surface
  // With the laws: their passes after a step, and the changes since the last take_spring_events().
  VkCommandBuffer events_commands_ = VK_NULL_HANDLE;
  std::uint32_t recorded_laws_ = 0;  // the laws events_commands_ was recorded for (live edits change them)
  IntegratorEvents events_;
  // With self-collision: the device's pass, made for the sheet as it is; the host's, for the steps
  // it finishes; the counts since the last take_self_contacts().
  std::optional<DeviceSelfContacts> self_;
  SelfContacts host_self_;
  IntegratorSelfContacts self_counts_;

  // Whether forces_'s force array holds f at the device's state (the last step's end).
  bool forces_current_ = false;
  // A restored run's first f0 is the one the saved run had reused: not counted again.
  bool uncounted_evaluation_ = false;
  bool exchanged_ = false;
  std::uint64_t exchanged_fingerprint_ = 0;
  std::uint64_t model_revision_ = 0;
  int last_iterations_ = 0;
};

}  // namespace clothsim::gpu
