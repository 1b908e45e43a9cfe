#include "gpu/device_integrator.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <span>

#include "core/assert.h"
#include "core/parallel.h"
#include "core/step_profile.h"
#include "core/timer.h"
#include "gpu/device_paths.h"
#include "gpu/gpu_error.h"
#include "gpu/real_arrays.h"
#include "gpu/shaders/device_step.h"
#include "gpu/state_transfer.h"
#include "integrators/dynamics.h"
#include "integrators/explicit_runge_kutta.h"

namespace clothsim::gpu {
namespace {

// input_staging_'s first size: the control arrays and a few anchors' and colliders' rows in float64.
constexpr std::uint64_t kInputStagingBytes = 4096;

// Symplectic Euler as a one-stage "tableau": K_0 at the state, and b = (1) for the work
// integrals; rk_solution forms its update itself (v + h K_0, then x + h v_new).
constexpr ButcherTableau kSymplecticEuler{"symplectic-euler", 1, 1, 0, {0.0}, {{{}}}, {1.0}, {}};

const ButcherTableau& tableau_for(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::rkf45: return kFehlberg45;
    case IntegratorKind::rk4: return kClassicRk4;
    case IntegratorKind::symplectic_euler: return kSymplecticEuler;
    case IntegratorKind::implicit_euler:
    case IntegratorKind::imex: break;
  }
  throw GpuError(std::string(to_string(kind)) + " does not run on the Vulkan backend");
}

// Attempts per submission: a batch large enough for a frame's steps in one or two submissions,
// small enough that the attempts left over after the target cost little (each returns at once).
constexpr std::uint32_t kMaxAttemptsPerSubmission = 256;

std::uint32_t workgroups_of(std::uint64_t items) { return workgroups_for(items, kReduceWorkgroup); }

// lattice_stage's tiles on a rows x cols lattice (0 x 0 off the lattice path: none).
std::uint32_t stage_tiles(std::size_t rows, std::size_t cols) {
  const auto tiles = [](std::size_t count) {
    return static_cast<std::uint32_t>((count + kStageTile - 1) / kStageTile);
  };
  return tiles(rows) * tiles(cols);
}

// The checks before anything is allocated: the device, its precision and its memory.
Device& checked(Device& device, const ClothModel& model, IntegratorKind kind, const DeviceSelection& selection,
                DeviceForcePath path) {
  device.require_precision(selection.precision);
  const std::uint32_t chained =
      DeviceIntegrator::chained_stages_for(device, selection.precision, selection.stage_passes, path);
  device.require_memory(DeviceIntegrator::device_bytes_for(element_counts(model), model.anchors.size(), kind,
                                                           selection.precision, path, model.colliders.size(), chained),
                        "the scene");
  return device;
}

// The lattice path (lattice_elements) on a lattice model unless the general kernel is asked for.
DeviceForcePath force_path(const ClothModel& model, const ForceOptions& options) {
  return model.layout == ModelLayout::lattice && options.kernel != ForceKernel::general ? DeviceForcePath::lattice
                                                                                        : DeviceForcePath::general;
}

std::vector<double> nystrom_rows(const ButcherTableau& tableau) {
  std::vector<std::array<double, kMaxStages>> weights;
  for (int i = 0; i < tableau.stages; ++i) weights.push_back(tableau.coefficients[static_cast<std::size_t>(i)]);
  weights.push_back(tableau.weights);
  std::array<double, kMaxStages> difference{};
  for (std::size_t i = 0; i < difference.size(); ++i) difference[i] = tableau.weights[i] - tableau.embedded_weights[i];
  weights.push_back(difference);
  std::vector<double> rows;
  for (const std::array<double, kMaxStages>& w : weights) {
    const NystromRow row = nystrom_row(tableau, w);
    rows.push_back(row.velocity_sum);
    rows.insert(rows.end(), row.position.begin(), row.position.end());
    rows.insert(rows.end(), row.velocity.begin(), row.velocity.end());
  }
  static_assert(kMaxStages == kMaxDeviceStages, "the device's rows have the CPU's width");
  return rows;
}

template <typename T>
std::span<const std::byte> bytes_of(const std::vector<T>& values) {
  return std::as_bytes(std::span(values));
}

}  // namespace

std::array<std::uint64_t, DeviceIntegrator::array_count> DeviceIntegrator::array_bytes(const LatticeCounts& counts,
                                                                                       int stages, Precision precision,
                                                                                       std::uint32_t anchor_capacity,
                                                                                       std::size_t colliders,
                                                                                       std::uint32_t chained_stages) {
  using A = DeviceIntegrator;
  const std::uint64_t real = real_size(precision);
  const std::uint64_t n = counts.particles;
  const std::uint64_t elements = counts.connectors + counts.radials;
  const std::uint64_t s = static_cast<std::uint64_t>(stages);
  std::array<std::uint64_t, A::array_count> bytes{};
  bytes[A::state_position] = bytes[A::state_velocity] = bytes[A::trial_position] = bytes[A::trial_velocity] =
      3 * n * real;
  bytes[A::state_position_low] = bytes[A::state_velocity_low] = splits_state(precision) ? 3 * n * real : real;
  // lattice_stage keeps the last stage's accelerations, and writes no springs' forces.
  const bool chained = chained_stages != 0;
  bytes[A::acceleration] = std::max<std::uint64_t>((chained ? s - 1 : s) * 3 * n * real, real);
  bytes[A::rows] = (s + 2) * kRowReals * real;
  bytes[A::control_real] = kControlReals * real;
  bytes[A::control_uint] = kControlUints * 4;
  bytes[A::particle_anchor] = n * 4;
  bytes[A::inverse_mass] = n * real;
  bytes[A::anchor_paths] = std::uint64_t{anchor_capacity} * kPathReals * real;
  // One block per workgroup of rk_solution, or per tile of lattice_stage's last stage (more).
  const std::uint64_t error_blocks = std::max<std::uint64_t>(workgroups_of(n), stage_tiles(counts.rows, counts.cols));
  bytes[A::block_error] = error_blocks * real;
  bytes[A::block_particle] = error_blocks * 4;
  bytes[A::particle_power] = 3 * n * real;
  bytes[A::block_work] = workgroups_of(std::max(n, elements)) * 3 * real;
  bytes[A::lattice_params] = n * kLatticeParams * real;
  bytes[A::lattice_forces] = chained ? real : n * kLatticeForces * real;
  bytes[A::event_params] = n * kEventParams * real;
  bytes[A::event_energy] = n * 2 * real;
  bytes[A::event_flags] = n * 4;
  bytes[A::block_events] = workgroups_of(n) * 2 * real;
  // The obstacle pass's arrays: a placeholder each without colliders (a pass binds every array).
  const bool obstacles = colliders > 0;
  bytes[A::colliders] = std::max<std::uint64_t>(colliders, 1) * kColliderReals * real;
  bytes[A::contact_before] = obstacles ? 6 * n * real : real;
  bytes[A::moved] = obstacles ? n * 4 : 4;
  bytes[A::block_obstacles] = obstacles ? workgroups_of(n) * kObstacleBlockReals * real : real;
  bytes[A::mesh_reals] = real;  // the meshes' own sizes besides
  bytes[A::mesh_uints] = std::max<std::uint64_t>(colliders, 1) * kMeshHeaderUints * 4;
  return bytes;
}

static_assert(kMaxChainedStagesFloat32 <= 3 && kMaxChainedStagesFloat64 <= 3,
              "lattice_stage.comp sizes its shared arrays for at most three chained stages");

std::uint32_t DeviceIntegrator::chained_stages_for(const Device& device, Precision precision,
                                                   std::optional<StagePasses> passes, DeviceForcePath path) {
  // Unset: a GPU chains; a CPU device (lavapipe) runs three passes a stage, which it runs faster
  // (docs/gpu.md, "Stages chained in a pass").
  const StagePasses chosen = passes.value_or(device.info().type == "cpu" ? StagePasses::split : StagePasses::chained);
  if (path != DeviceForcePath::lattice || chosen == StagePasses::split) return 0;
  if (chosen == StagePasses::fused) return 1;
  return precision == Precision::float64 ? kMaxChainedStagesFloat64 : kMaxChainedStagesFloat32;
}

std::uint64_t DeviceIntegrator::device_bytes_for(const LatticeCounts& counts, std::size_t anchors, IntegratorKind kind,
                                                 Precision precision, DeviceForcePath path, std::size_t colliders,
                                                 std::uint32_t chained_stages) {
  const int stages = tableau_for(kind).stages;
  std::uint64_t total = DeviceForces::bytes_for(counts, precision, static_cast<std::uint32_t>(stages), path);
  for (std::uint64_t bytes :
       array_bytes(counts, stages, precision, anchor_row_capacity(anchors), colliders, chained_stages)) {
    total += bytes;
  }
  total += StateChecksPass::bytes_for(counts, path);
  return total;
}

DeviceIntegrator::DeviceIntegrator(const ClothModel& model, const IntegratorSettings& settings,
                                   const ForceOptions& options, const DeviceSelection& selection)
    : model_(model),
      settings_(settings),
      options_(options),
      tableau_(tableau_for(settings.kind)),
      adaptive_(settings.kind == IntegratorKind::rkf45),
      symplectic_(settings.kind == IntegratorKind::symplectic_euler),
      lattice_(force_path(model, options) == DeviceForcePath::lattice),
      precision_(selection.precision),
      device_(DeviceOptions{selection.index, selection.validation}),
      forces_(checked(device_, model, settings.kind, selection, force_path(model, options)), model, selection.precision,
              options.terms, static_cast<std::uint32_t>(tableau_.stages), force_path(model, options)),
      particles_(forces_.particle_count()),
      elements_(forces_.element_count()),
      anchor_capacity_(anchor_row_capacity(model.anchors.size())),
      control_real_readback_(device_, kControlReals * real_size(precision_), Memory::host_visible),
      control_uint_readback_(device_, kControlUints * 4, Memory::host_visible),
      state_staging_(device_, std::uint64_t{particles_} * (splits_state(precision_) ? 12 : 6) * real_size(precision_),
                     Memory::host_visible),
      input_staging_(device_, kInputStagingBytes, Memory::host_visible),
      stage_state_pass_(shader_pipeline(device_, "rk_stage_state", precision_, 12, sizeof(StagePassConstants))),
      lattice_pass_(shader_pipeline(device_, "lattice_elements", precision_, 10, sizeof(LatticePassConstants))),
      acceleration_pass_(shader_pipeline(device_, "stage_acceleration", precision_, 16, sizeof(StagePassConstants))),
      lattice_stage_pass_(shader_pipeline(device_, "lattice_stage", precision_, 22, sizeof(LatticePassConstants))),
      solution_pass_(
          shader_pipeline(device_, "rk_solution", precision_, 16, sizeof(StagePassConstants), kReduceWorkgroup)),
      control_pass_(
          shader_pipeline(device_, "rk_control", precision_, 7, sizeof(ReducePassConstants), kReduceWorkgroup)),
      events_connectors_pass_(
          shader_pipeline(device_, "lattice_events_connectors", precision_, 7, sizeof(EventPassConstants))),
      events_radial_pass_(shader_pipeline(device_, "lattice_events_radial", precision_, 7, sizeof(EventPassConstants),
                                          kReduceWorkgroup)),
      accept_pass_(
          shader_pipeline(device_, "rk_accept", precision_, 14, sizeof(AcceptPassConstants), kReduceWorkgroup)),
      obstacle_contacts_pass_(
          shader_pipeline(device_, "obstacle_contacts", precision_, 17, sizeof(ObstaclePassConstants))),
      obstacle_energy_pass_(shader_pipeline(device_, "obstacle_energy", precision_, 15, sizeof(ObstaclePassConstants),
                                            kReduceWorkgroup)) {
  chained_stages_ = chained_stages_for(device_, precision_, selection.stage_passes, force_path(model, options));
  if (!lattice_ && model.limits.changes_sheet()) {
    throw GpuError("tearing, permanent stretching and creasing run on the device on a lattice sheet only");
  }
  if (!lattice_ && !model.colliders.empty()) throw GpuError("obstacles run on the device on a lattice sheet only");
  // The obstacles' arrays as placeholders; prepare_obstacles() sizes them for the colliders.
  const auto bytes =
      array_bytes(element_counts(model), tableau_.stages, precision_, anchor_capacity_, 0, chained_stages_);
  arrays_.reserve(array_count);
  for (std::uint32_t a = 0; a < array_count; ++a) arrays_.emplace_back(device_, bytes[a], Memory::device_local);
  upload(device_, arrays_[rows], real_bytes(nystrom_rows(tableau_), precision_));
  if (StateChecksPass::runs_on(device_)) {
    state_checks_.emplace(device_, precision_, element_counts(model), force_path(model, options));
  }
  bind_passes();
  prepare_obstacles();
}

void DeviceIntegrator::bind_passes() {
  using F = DeviceForces;
  const auto bind = [&](ComputePipeline& pass, std::initializer_list<const Buffer*> buffers) {
    pass.bind(std::vector<const Buffer*>(buffers));
  };
  const auto own = [&](Array a) { return &arrays_[a]; };
  const auto forces = [&](F::Array a) { return &forces_.buffer(a); };
  // float32: the trial state's low parts, in the stage arrays (free from rk_solution on).
  const auto trial_low = forces;
  bind(stage_state_pass_, {own(state_position), own(state_velocity), own(acceleration), own(rows), own(control_real),
                           own(control_uint), own(particle_anchor), own(anchor_paths), forces(F::position),
                           forces(F::velocity), own(state_position_low), own(state_velocity_low)});
  bind(acceleration_pass_, {forces(F::velocity), forces(F::particle_mass), own(inverse_mass), forces(F::environment),
                            forces(F::gather_offset), forces(F::gather_slot), forces(F::slot_force), own(rows),
                            own(control_real), own(control_uint), own(particle_anchor), own(anchor_paths),
                            own(acceleration), own(particle_power), own(lattice_forces), own(state_velocity)});
  // The force passes read the stage as offsets from the state in float32 (shaders/stage_offsets.glsl).
  bind(lattice_pass_,
       {forces(F::position), forces(F::velocity), own(lattice_params), own(lattice_forces), own(particle_power),
        own(control_uint), own(event_params), own(state_position), own(state_velocity), own(rows)});
  bind(lattice_stage_pass_, {own(state_position),      own(state_velocity), own(state_position_low),
                             own(state_velocity_low),  own(acceleration),   own(rows),
                             own(control_real),        own(control_uint),   own(particle_anchor),
                             own(anchor_paths),        own(lattice_params), own(event_params),
                             forces(F::particle_mass), own(inverse_mass),   forces(F::environment),
                             own(particle_power),      own(trial_position), own(trial_velocity),
                             own(block_error),         own(block_particle), trial_low(F::position),
                             trial_low(F::velocity)});
  if (!lattice_) forces_.read_origin_from(arrays_[state_position], arrays_[state_velocity]);
  bind(solution_pass_, {own(state_position), own(state_velocity), own(acceleration), own(rows), own(control_real),
                        own(control_uint), own(particle_anchor), own(anchor_paths), own(trial_position),
                        own(trial_velocity), own(block_error), own(block_particle), own(state_position_low),
                        own(state_velocity_low), trial_low(F::position), trial_low(F::velocity)});
  bind(control_pass_, {own(control_real), own(control_uint), own(block_error), own(block_particle), own(block_work),
                       own(block_events), own(block_obstacles)});
  // The explicit methods hold no particle on a surface (`holds` 0): the surface contacts, impulses
  // and holds are never read, and other arrays stand in for them.
  bind(obstacle_contacts_pass_,
       {own(control_real), own(control_uint), own(state_position), own(trial_position), own(trial_velocity),
        own(particle_anchor), own(colliders), own(contact_before), own(moved), own(mesh_reals), own(mesh_uints),
        trial_low(F::position), trial_low(F::velocity), own(contact_before), own(contact_before), own(moved),
        forces(F::particle_mass)});
  bind(obstacle_energy_pass_,
       {own(control_real), own(control_uint), own(trial_position), own(trial_velocity), own(contact_before), own(moved),
        own(particle_anchor), own(colliders), forces(F::particle_mass), forces(F::environment), own(lattice_params),
        own(event_params), own(block_obstacles), own(mesh_reals), own(mesh_uints)});
  bind(events_connectors_pass_, {own(state_position), own(lattice_params), own(event_params), own(event_energy),
                                 own(event_flags), own(control_real), own(control_uint)});
  bind(events_radial_pass_, {own(state_position), own(lattice_params), own(event_params), own(event_energy),
                             own(event_flags), own(control_uint), own(block_events)});
  if (state_checks_) {
    const bool split = splits_state(precision_);
    const StateArray position{own(state_position), split ? own(state_position_low) : nullptr};
    const StateArray velocity{own(state_velocity), split ? own(state_velocity_low) : nullptr};
    if (lattice_) {
      state_checks_->bind_lattice(position, velocity, *forces(F::particle_mass), *own(lattice_params),
                                  *own(event_params));
    } else {
      state_checks_->bind_elements(position, velocity, forces_);
    }
  }
  bind(accept_pass_,
       {own(control_real), own(control_uint), own(trial_position), own(trial_velocity), own(state_position),
        own(state_velocity), forces(F::element_power), own(particle_power), own(rows), own(block_work),
        trial_low(F::position), trial_low(F::velocity), own(state_position_low), own(state_velocity_low)});
}

DeviceIntegrator::~DeviceIntegrator() = default;  // the command buffers go with the device's pool

std::uint32_t DeviceIntegrator::rk_accept_items() const {
  // The particles, and on the general path the elements, whose damping power it sums.
  return std::max(particles_, lattice_ ? 0u : elements_);
}

std::uint32_t DeviceIntegrator::rk_accept_blocks() const { return workgroups_of(rk_accept_items()); }

std::uint32_t DeviceIntegrator::lattice_stage_invocations() const {
  // A workgroup of kStageTile x kStageTile invocations a tile (lattice_stage.comp, device_step.h).
  return stage_tiles(static_cast<std::size_t>(model_.rows), static_cast<std::size_t>(model_.cols)) * kStageTile *
         kStageTile;
}

void DeviceIntegrator::record_attempt(VkCommandBuffer commands, PassTimer& timer) const {
  const auto stages = static_cast<std::uint32_t>(tableau_.stages);
  const std::uint32_t lattice_cols = lattice_ ? static_cast<std::uint32_t>(model_.cols) : 0u;
  const std::uint32_t damped = (options_.terms & kSpringDamping) != 0 ? 1u : 0u;
  const std::uint32_t symplectic = symplectic_ ? 1u : 0u;
  const auto lattice_constants = [&](std::uint32_t stage) {
    return LatticePassConstants{particles_,
                                static_cast<std::uint32_t>(model_.rows),
                                lattice_cols,
                                damped,
                                stage,
                                stages,
                                params_particle_,
                                symplectic,
                                1};
  };
  std::uint32_t error_blocks = workgroups_of(particles_);
  if (chained_stages_ != 0) {
    // lattice_stage, chained_stages_ stages a pass; the pass that ends the attempt forms the trial
    // state and each tile's largest error too (timed with the forces).
    for (std::uint32_t first = 0; first < stages; first += chained_stages_) {
      LatticePassConstants lattice = lattice_constants(first);
      lattice.pass_stages = std::min(chained_stages_, stages - first);
      lattice_stage_pass_.dispatch(commands, &lattice, lattice_stage_invocations());
      timer.mark(commands, StepStage::forces);
    }
    error_blocks = stage_tiles(static_cast<std::size_t>(model_.rows), static_cast<std::size_t>(model_.cols));
  } else {
    for (std::uint32_t i = 0; i < stages; ++i) {
      const StagePassConstants stage{particles_, i, stages, 0, lattice_cols};
      stage_state_pass_.dispatch(commands, &stage, particles_);
      timer.mark(commands, StepStage::stage_sums);
      if (lattice_) {
        const LatticePassConstants lattice = lattice_constants(i);
        lattice_pass_.dispatch(commands, &lattice, particles_);
      } else {
        forces_.record_element_passes(commands, i);
      }
      acceleration_pass_.dispatch(commands, &stage, particles_);
      timer.mark(commands, StepStage::forces);
    }
    const StagePassConstants solution{particles_, 0, stages, symplectic, lattice_cols};
    solution_pass_.dispatch(commands, &solution, particles_);
  }
  const std::uint32_t obstacles = runs_obstacle_contacts() ? 1u : 0u;
  const std::uint32_t element_items = lattice_ ? 0u : elements_;  // the lattice path's damping is per particle
  const std::uint32_t accept_blocks = rk_accept_blocks();
  // Without obstacles the decision first adds the work of the step accepted before (rk_control's
  // phase 1, which then has no dispatch of its own; the submission's last step's, phase 3).
  const std::uint32_t work_blocks = obstacles != 0u ? 0u : accept_blocks;
  const ReducePassConstants decide{particles_, error_blocks, 0, stages, obstacles, work_blocks};
  control_pass_.dispatch(commands, &decide, kReduceWorkgroup);
  timer.mark(commands, StepStage::solution_and_error);
  if (obstacles != 0u) record_obstacle_passes(commands, timer);
  const AcceptPassConstants accept{particles_, element_items, stages, accept_blocks, lattice_ ? 1u : 0u};
  accept_pass_.dispatch(commands, &accept, rk_accept_items());
  if (obstacles != 0u) {
    // Phase 1 reads rk_accept's blocks and the obstacle passes': one per kReduceWorkgroup
    // particles both, on the lattice path, where obstacles run.
    const ReducePassConstants collect{particles_, accept_blocks, 1, stages, obstacles, 0};
    control_pass_.dispatch(commands, &collect, kReduceWorkgroup);
  }
  timer.mark(commands, StepStage::solution_update);
  if (laws_ != 0) {
    // Tearing, stretching and creasing on the accepted state (events/spring_events.h), then their
    // work into the advance's sums.
    const EventPassConstants events{particles_, static_cast<std::uint32_t>(model_.rows),
                                    static_cast<std::uint32_t>(model_.cols), laws_, workgroups_of(particles_)};
    events_connectors_pass_.dispatch(commands, &events, particles_);
    events_radial_pass_.dispatch(commands, &events, particles_);
    const ReducePassConstants collect_events{particles_, workgroups_of(particles_), 2, stages, obstacles, 0};
    control_pass_.dispatch(commands, &collect_events, kReduceWorkgroup);
    timer.mark(commands, StepStage::events);
  }
}

DeviceIntegrator::RecordedAttempts& DeviceIntegrator::attempts_buffer(std::uint32_t attempts) {
  const auto found = recorded_.find(attempts);
  if (found != recorded_.end()) return found->second;
  // Marks per attempt: two per stage (its state, its forces), the decision, the obstacles, the
  // acceptance, the events; and the last step's work.
  const auto marks_per_attempt = static_cast<std::uint32_t>(2 * tableau_.stages + 4);
  RecordedAttempts recorded;
  recorded.timer = std::make_unique<PassTimer>(device_, attempts * marks_per_attempt + 1);
  recorded.commands = device_.record([&](VkCommandBuffer c) {
    recorded.timer->begin(c);
    for (std::uint32_t a = 0; a < attempts; ++a) record_attempt(c, *recorded.timer);
    if (!runs_obstacle_contacts()) {
      // The last accepted step's work, which no next decision adds (rk_control's phase 3).
      const ReducePassConstants last{particles_, rk_accept_blocks(), 3, static_cast<std::uint32_t>(tableau_.stages), 0,
                                     0};
      control_pass_.dispatch(c, &last, kReduceWorkgroup);
      recorded.timer->mark(c, StepStage::solution_update);
    }
    record_readback(c, arrays_[control_real], control_real_readback_, control_real_readback_.bytes());
    record_readback(c, arrays_[control_uint], control_uint_readback_, control_uint_readback_.bytes());
  });
  return recorded_.emplace(attempts, std::move(recorded)).first->second;
}

void DeviceIntegrator::release_recorded() {
  for (const auto& [attempts, recorded] : recorded_) device_.release(recorded.commands);
  recorded_.clear();
}

void DeviceIntegrator::write_anchor_paths(double t0) {
  if (model_.anchors.size() > anchor_capacity_) {
    // More anchors than the table holds (pins added at run time): a larger table, bound anew,
    // and the recorded command buffers, which name the old one, recorded again.
    anchor_capacity_ = 2 * static_cast<std::uint32_t>(model_.anchors.size());
    arrays_[anchor_paths] =
        Buffer(device_, std::uint64_t{anchor_capacity_} * kPathReals * real_size(precision_), Memory::device_local);
    bind_passes();
    release_recorded();
  }
  std::vector<double> paths;
  paths.reserve(model_.anchors.size() * kPathReals);
  for (const Anchor& anchor : model_.anchors) append_path_row(paths, anchor.path, t0, Vec3{});
  if (!paths.empty()) upload_input(arrays_[anchor_paths], real_bytes(paths, precision_));
}

void DeviceIntegrator::upload_input(Buffer& destination, std::span<const std::byte> bytes) {
  if (input_staging_.bytes() < bytes.size()) {
    input_staging_ =
        Buffer(device_, std::max<std::uint64_t>(bytes.size(), 2 * input_staging_.bytes()), Memory::host_visible);
  }
  upload(device_, destination, bytes, &input_staging_);
}

// An advance, as named stages: what changed goes up, the first step is chosen as on the CPU, the
// control arrays are written, batches of attempts run until the device says the advance is over,
// and the state and the counters come back.
StepOutcome DeviceIntegrator::run(ClothState& state, double t_limit, std::uint32_t max_accepted) {
  CLOTHSIM_ASSERT(t_limit > state.time, "step() needs a limit after the current time");
  const double t0 = state.time;
  {
    StageTimer timer(profile_, StepStage::device_transfers);
    upload_changes(state);
    write_anchor_paths(t0);
    upload_colliders(t0);
  }
  // The first step lands on the target or on the first impact ahead, as the Simulation limits a
  // step on the CPU; the device limits the later ones itself.
  const double arrival = first_arrival(state);
  const double step_limit = std::min(t_limit, arrival);
  bool clipped = false;
  const double h = clip_step(t0, first_step(state, t_limit), step_limit, clipped);
  if (adaptive_ && h < settings_.min_step && !clipped) return {StepStatus::step_underflow, h, 0, false};
  write_control(ControlStart{h, clipped, t_limit - t0, step_limit - t0, arrival - t0}, max_accepted);
  const Control control = run_attempts(max_accepted);
  {
    StageTimer timer(profile_, StepStage::device_transfers);
    read_state(state);
  }
  return take_results(state, t0, t_limit, control);
}

double DeviceIntegrator::first_step(const ClothState& state, double t_limit) {
  if (!adaptive_) return settings_.time_step;
  if (proposed_step_ <= 0.0) {
    if (settings_.time_step > 0.0) {
      proposed_step_ = settings_.time_step;
    } else {
      // time_step 0: the CPU's automatic first step, from one evaluation on the host.
      ClothDynamics dynamics(model_, options_);
      StateDerivative rate;
      rate.resize(model_.particle_count());
      dynamics.evaluate(state.time, state.position, state.velocity, rate);
      proposed_step_ = initial_adaptive_step(model_, settings_, state, rate.velocity_rate, t_limit);
      ++stats_.force_evaluations;
    }
  }
  return std::min(proposed_step_, settings_.max_step);
}

void DeviceIntegrator::write_control(const ControlStart& start, std::uint32_t max_accepted) {
  std::vector<double> reals(kControlReals, 0.0);
  reals[kStep] = start.step;
  reals[kProposedStep] = proposed_step_;
  reals[kPreviousError] = previous_error_;
  reals[kTarget] = start.target;
  reals[kStepLimit] = start.step_limit;
  reals[kArrival] = std::isfinite(start.arrival) ? start.arrival : CLOTHSIM_NO_ARRIVAL;
  reals[kThickness] = model_.collision.thickness;
  reals[kSmallestStep] = 1e30;  // within float's range
  reals[kMinStep] = settings_.min_step;
  reals[kMaxStep] = settings_.max_step;
  reals[kSafety] = settings_.safety;
  reals[kMaxGrowth] = settings_.max_growth;
  reals[kMaxShrink] = settings_.max_shrink;
  reals[kAbsoluteTolerance] = settings_.absolute_tolerance;
  reals[kRelativeTolerance] = settings_.relative_tolerance;
  reals[kFixedStep] = settings_.time_step;
  reals[kHardening] = model_.limits.hardening;
  std::vector<std::uint32_t> uints(kControlUints, 0u);
  uints[kActive] = 1;
  uints[kClipped] = start.clipped ? 1 : 0;
  uints[kMaxAccepted] = max_accepted;
  uints[kAdaptive] = adaptive_ ? 1 : 0;
  StageTimer timer(profile_, StepStage::device_transfers);
  upload_input(arrays_[control_real], real_bytes(reals, precision_));
  upload_input(arrays_[control_uint], bytes_of(uints));
}

DeviceIntegrator::Control DeviceIntegrator::run_attempts(std::uint32_t max_accepted) {
  // Batches of attempts until the advance ends: as many as the last advance took (a power of
  // two), then each batch twice the last.
  std::uint32_t attempts =
      max_accepted == 1 ? 1 : std::bit_ceil(std::min(expected_attempts_, kMaxAttemptsPerSubmission));
  Control control;
  control.uints.resize(kControlUints);
  for (;;) {
    // The device's time per stage from the passes' timestamps; "device steps" is the rest of the
    // wait (the submission, the control's read-back, what the timestamps do not cover).
    RecordedAttempts& recorded = attempts_buffer(attempts);
    const Stopwatch wait;
    device_.run(recorded.commands);
    const double waited = wait.seconds();
    recorded.timer->add_to(profile_);
    profile_.add(StepStage::device_steps, std::max(0.0, waited - recorded.timer->last_seconds()));
    std::memcpy(control.uints.data(), control_uint_readback_.mapped(), kControlUints * 4);
    if (control.uints[kActive] == 0) break;
    attempts = std::min(2 * attempts, kMaxAttemptsPerSubmission);
  }
  control.reals =
      reals_from_bytes(std::span(control_real_readback_.mapped(), kControlReals * real_size(precision_)), precision_);
  return control;
}

StepOutcome DeviceIntegrator::take_results(ClothState& state, double t0, double t_limit, const Control& control) {
  const std::vector<double>& reals = control.reals;
  const std::vector<std::uint32_t>& uints = control.uints;
  const bool at_target = reals[kElapsed] >= reals[kTarget];
  state.time = at_target ? t_limit : t0 + reals[kElapsed];
  // Anchored particles as ExplicitRungeKutta::accept leaves them: on their paths at the new time,
  // with the velocity after it (a keyframed path's next segment at a key). The device keeps its
  // own copy, which it never reads: each advance puts anchored particles on their paths.
  for (const Anchor& anchor : model_.anchors) {
    state.position[anchor.particle] = anchor.path.position(state.time);
    state.velocity[anchor.particle] = anchor.path.velocity_at(state.time);
  }
  exchanged_fingerprint_ = state_fingerprint(state, options_.threads);
  state.damping_work += reals[kWork] + reals[kWork + 1];
  state.drag_work += reals[kWork + 2] + reals[kWork + 3];
  state.anchor_work += reals[kWork + 4] + reals[kWork + 5];
  state.fracture_work += reals[kWork + 6] + reals[kWork + 7];
  state.plastic_work += reals[kWork + 8] + reals[kWork + 9];
  state.contact_work += reals[kWork + 2 * kContactWork] + reals[kWork + 2 * kContactWork + 1];
  if (runs_obstacle_contacts() && uints[kAcceptedSteps] > 0) {
    contacts_.last = uints[kContacts];
    contacts_.steps += uints[kContactSteps];
    contacts_.most = std::max<std::size_t>(contacts_.most, uints[kMostContacts]);
  }
  if (uints[kBreaks] + uints[kYields] + uints[kCreases] > 0) {
    events_.breaks += uints[kBreaks];
    events_.yields += uints[kYields];
    events_.creases += uints[kCreases];
    events_t0_ = t0;
  }
  proposed_step_ = reals[kProposedStep];
  previous_error_ = reals[kPreviousError];
  expected_attempts_ = std::max(1u, uints[kAttempts]);
  stats_.accepted_steps += uints[kAcceptedSteps];
  stats_.rejected_steps += uints[kRejectedSteps];
  stats_.force_evaluations += std::uint64_t{uints[kAttempts]} * static_cast<std::uint64_t>(tableau_.stages);
  if (uints[kAcceptedSteps] > 0) {
    stats_.smallest_step = std::min(stats_.smallest_step, reals[kSmallestStep]);
    stats_.largest_step = std::max(stats_.largest_step, reals[kLargestStep]);
    stats_.last_step = reals[kTakenStep];
  }
  if (uints[kStatus] != 0) {
    const auto status = uints[kStatus] == 1 ? StepStatus::step_underflow : StepStatus::non_finite;
    return {status, std::min(reals[kProposedStep], reals[kStep]), uints[kFailedParticle], uints[kNonFiniteError] != 0};
  }
  return {StepStatus::ok, reals[kTakenStep], 0, false};
}

double DeviceIntegrator::traffic_per_particle_and_attempt() const {
  if (!lattice_) return 0.0;
  const auto real = static_cast<double>(real_size(precision_));
  const double index = 4.0;
  const auto stages = static_cast<std::size_t>(tableau_.stages);
  const std::vector<double> row_reals = nystrom_rows(tableau_);
  // float32: the stages as offsets from the state (shaders/stage_offsets.glsl), the state as two
  // floats a coordinate (shaders/split_state.glsl).
  const double origin = splits_state(precision_) ? 6.0 : 0.0;
  const double low = splits_state(precision_) ? 6.0 : 0.0;
  double reals = 0.0;
  double indices = 0.0;
  // Whether Nystrom row `row` (a stage's, then the solution's and the error's) weighs stage l.
  const auto weighs = [&](std::size_t row, std::size_t l) {
    const std::size_t base = row * kRowReals;
    return row_reals[base + 1 + l] != 0.0 || row_reals[base + 1 + kMaxDeviceStages + l] != 0.0;
  };
  const double params = params_particle_ == kOwnParams ? kLatticeParams + 2 : 0.0;
  if (chained_stages_ != 0) {
    // lattice_stage, a pass for each chained_stages_ stages from `first`: the state and low parts
    // in (its neighbours' as cached), the earlier passes' accelerations any of its stages weighs,
    // the spring parameters, mass and inverse mass once; for each stage its acceleration out; the
    // three power sums read (after stage 0) and written once; no stage state, springs' forces or
    // (within the pass) accelerations between passes. The pass that ends the attempt also forms the trial state:
    // the accelerations only the solution or error rows weigh in, the trial state out, and the
    // last stage's acceleration kept, not written.
    const std::size_t chain = chained_stages_;
    for (std::size_t first = 0; first < stages; first += chain) {
      const std::size_t end = std::min(stages, first + chain);
      std::size_t earlier = 0;
      for (std::size_t l = 0; l < first; ++l) {
        bool weighed = false;
        for (std::size_t i = first; i < end; ++i) weighed = weighed || weighs(i, l);
        if (end == stages) weighed = weighed || weighs(stages, l) || weighs(stages + 1, l);
        if (weighed) ++earlier;
      }
      const double powers = first == 0 ? 3 : 6;
      reals +=
          6 + low + 3 * static_cast<double>(earlier) + params + 1 + 1 + powers + 3 * static_cast<double>(end - first);
      indices += 1;  // the particle's anchor
    }
    reals += 6 + low - 3;
  } else {
    for (std::size_t i = 0; i < stages; ++i) {
      // The earlier stages' accelerations stage i's Nystrom row weighs.
      std::size_t weighed = 0;
      for (std::size_t l = 0; l < i; ++l) {
        if (weighs(i, l)) ++weighed;
      }
      // rk_stage_state: the state in, the stage state out, and those accelerations.
      reals += 6 + low + 6 + 3 * static_cast<double>(weighed);
      indices += 1;  // the particle's anchor
      // lattice_elements: the stage state (in float32 its offsets, and the state they are from),
      // the particle's spring parameters and its two connectors' original lengths in (on a uniform
      // sheet one particle's, read once for all); its force and its four neighbours' shares out,
      // and its damping power sum read and written.
      reals += 6 + origin + params + kLatticeForces + 2;
      // stage_acceleration: the stage velocity (in float32 its offset and the state's), mass and
      // inverse mass, the forces gathered, the acceleration out, the drag and anchor power sums
      // read and written.
      reals += 3 + origin / 2 + 1 + 1 + kLatticeForces + 3 + 4;
      indices += 1;
    }
    // rk_solution: the state and every stage's acceleration in, the trial state out.
    reals += 12 + 2 * low + 3 * static_cast<double>(stages);
  }
  indices += 1;
  // rk_accept: the trial state in, the state out, the three power sums in.
  reals += 12 + 2 * low + 3;
  if (runs_obstacle_contacts()) {
    // obstacle_contacts: the step's start and the trial state in, the moved flag out and, for a
    // moved particle, its state before the pass and after it (counted as if every particle moved).
    reals += 3 + 6 + 6 + 6;
    indices += 2;  // the anchor, the flag
    // obstacle_energy: the state after the pass, the mass and, where particles moved, their state
    // before it and their springs' parameters and arms' original lengths (counted the same way).
    reals += 6 + 1 + 6 + kLatticeParams + 2;
    indices += 2;
  }
  if (laws_ != 0) {
    // The events: each pass reads the state, its springs' parameters (the connectors' 8, the
    // radial springs' 24) and the particle's event parameters, and writes its energies.
    reals += (3 + 8 + kEventParams + 2) + (3 + 24 + kEventParams + 2);
    indices += 1;  // the broken connectors' flags
  }
  return reals * real + indices * index;
}

std::string DeviceIntegrator::profile_notes() const {
  if (!lattice_) return {};
  char line[160];
  std::snprintf(line, sizeof line,
                "device traffic: %.0f bytes per particle and attempt (%s, counted from the passes' arrays)\n",
                traffic_per_particle_and_attempt(), to_string(precision_));
  return line;
}

std::size_t DeviceIntegrator::workspace_bytes() const { return first_arrival_.bytes(); }

void DeviceIntegrator::transfer_state(StateArchive& archive) {
  Integrator::transfer_state(archive);
  if (adaptive_) {
    archive.value("rkf45.proposed_step", proposed_step_);
    archive.value("rkf45.previous_error", previous_error_);
  }
}

}  // namespace clothsim::gpu
