#include "gpu/device_implicit_euler.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>

#include "core/assert.h"
#include "core/step_profile.h"
#include "core/timer.h"
#include "gpu/device_paths.h"
#include "gpu/gpu_error.h"
#include "gpu/real_arrays.h"
#include "integrators/block_system.h"
#include "integrators/dynamics.h"

namespace clothsim::gpu {
namespace {

std::uint32_t reduce_workgroups(std::uint64_t items) { return workgroups_for(items, kImplicitReduceWorkgroup); }

}  // namespace

std::array<std::uint64_t, DeviceImplicitEuler::array_count> DeviceImplicitEuler::array_bytes(
    const LatticeCounts& counts, Precision precision, std::uint32_t anchor_capacity, std::size_t colliders,
    bool self_collision) {
  using A = DeviceImplicitEuler;
  const std::uint64_t real = real_size(precision);
  const std::uint64_t n = counts.particles;
  std::array<std::uint64_t, A::array_count> bytes{};
  bytes[A::connector_factors] = std::uint64_t{counts.connectors} * kConnectorFactorReals * real;
  bytes[A::radial_factors] = std::uint64_t{counts.radials} * kRadialFactorReals * real;
  bytes[A::particle_anchor] = n * 4;
  for (A::Array a : {A::solution, A::rhs, A::residual, A::preconditioned, A::direction, A::product}) {
    bytes[a] = 3 * n * real;
  }
  bytes[A::jacobi] = 9 * n * real;
  const bool obstacles = colliders > 0 || self_collision;  // the obstacle pass's arrays
  const std::uint64_t obstacle_blocks =
      obstacles ? DeviceImplicitEuler::obstacle_blocks(counts.particles, counts.connectors, counts.radials) : 0;
  // The laws' passes write theirs there too: one block per workgroup of connectors, then of radial springs.
  const std::uint64_t event_blocks =
      std::uint64_t{reduce_workgroups(counts.connectors)} + reduce_workgroups(counts.radials);
  bytes[A::block_sums] = std::max({std::uint64_t{reduce_workgroups(n)}, obstacle_blocks, event_blocks}) * 3 * real;
  bytes[A::solve_real] = kSolveReals * real;
  bytes[A::solve_uint] = kSolveUints * 4;
  bytes[A::anchor_rows] = std::uint64_t{anchor_capacity} * kAnchorRowReals * real;
  bytes[A::hold] = bytes[A::slipped] = n * 4;
  bytes[A::surface_contacts] = obstacles ? n * kContactReals * real : 0;
  bytes[A::impulse] = bytes[A::start_position] = obstacles ? 3 * n * real : 0;
  bytes[A::contact_before] = obstacles ? 6 * n * real : 0;
  bytes[A::moved] = obstacles ? n * 4 : 0;
  bytes[A::colliders] = colliders * kColliderReals * real;
  bytes[A::obstacle_control_real] = obstacles ? kControlReals * real : 0;
  bytes[A::obstacle_control_uint] = obstacles ? kControlUints * 4 : 0;
  // The laws' per-spring values (allocated whether the model has laws or not: a model's limits are
  // the scene's, and the memory check before the model is built does not know them).
  bytes[A::connector_events] = std::uint64_t{counts.connectors} * kEventsPerConnector * real;
  bytes[A::radial_arms] = std::uint64_t{counts.radials} * 2 * 4;
  bytes[A::radial_yield_angle] = std::uint64_t{counts.radials} * real;
  bytes[A::connector_broke] = std::uint64_t{counts.connectors} * 4;
  // A Buffer holds at least 16 bytes (a sheet without radial springs, say).
  for (std::uint64_t& b : bytes) b = std::max<std::uint64_t>(b, 16);
  return bytes;
}

namespace {

// The checks before anything is allocated: the device, its precision and its memory.
Device& checked(Device& device, const ClothModel& model, Precision precision, const IntegratorSettings& settings) {
  device.require_precision(precision);
  device.require_memory(DeviceImplicitEuler::device_bytes_for(element_counts(model), model.anchors.size(), precision,
                                                              model.colliders.size(), settings, model.collision.self),
                        "the scene");
  return device;
}

ComputePipeline make_pass(Device& device, const char* name, Precision precision, std::uint32_t bindings,
                          std::uint32_t workgroup = 64) {
  return shader_pipeline(device, name, precision, bindings, sizeof(ImplicitPassConstants), workgroup);
}

}  // namespace

std::uint64_t DeviceImplicitEuler::device_bytes_for(const LatticeCounts& counts, std::size_t anchors,
                                                    Precision precision, std::size_t colliders,
                                                    const IntegratorSettings& settings, bool self_collision) {
  std::uint64_t total = DeviceForces::bytes_for(counts, precision, 1, DeviceForcePath::general);
  for (std::uint64_t bytes : array_bytes(counts, precision, anchor_row_capacity(anchors), colliders, self_collision)) {
    total += bytes;
  }
  if (self_collision) total += DeviceSelfContacts::bytes_for(counts, precision);
  total += StateChecksPass::bytes_for(counts, DeviceForcePath::general);
  if (DeviceMultigrid::applies(counts, settings)) {
    total += DeviceMultigrid::bytes_for(static_cast<std::uint32_t>(counts.rows),
                                        static_cast<std::uint32_t>(counts.cols), precision, settings.cg_line_smoother);
  }
  return total;
}

DeviceImplicitEuler::DeviceImplicitEuler(const ClothModel& model, const IntegratorSettings& settings,
                                         const ForceOptions& options, const DeviceSelection& selection)
    : model_(model),
      settings_(settings),
      options_(options),
      precision_(selection.precision),
      device_(DeviceOptions{selection.index, selection.validation}),
      forces_(checked(device_, model, selection.precision, settings), model, selection.precision, options.terms, 1,
              DeviceForcePath::general),
      particles_(forces_.particle_count()),
      connectors_(static_cast<std::uint32_t>(model.connector_count())),
      radials_(static_cast<std::uint32_t>(model.radial_count())),
      anchor_capacity_(anchor_row_capacity(model.anchors.size())),
      real_input_(device_, kSolveReals * real_size(precision_), Memory::host_visible),
      uint_input_(device_, kSolveUints * 4, Memory::host_visible),
      anchor_input_(device_, std::uint64_t{anchor_capacity_} * kAnchorRowReals * real_size(precision_),
                    Memory::host_visible),
      real_output_(device_, kSolveReals * real_size(precision_), Memory::host_visible),
      uint_output_(device_, kSolveUints * 4, Memory::host_visible),
      state_staging_(device_, std::uint64_t{particles_} * 6 * real_size(precision_), Memory::host_visible),
      linearize_pass_(make_pass(device_, "implicit_linearize", precision_, 15)),
      product_pass_(make_pass(device_, "implicit_product", precision_, 8)),
      gather_pass_(make_pass(device_, "implicit_gather", precision_, 20, kImplicitReduceWorkgroup)),
      diagonal_pass_(make_pass(device_, "implicit_diagonal", precision_, 17)),
      reduce_pass_(make_pass(device_, "implicit_reduce", precision_, 3, kImplicitReduceWorkgroup)),
      iterate_pass_(make_pass(device_, "implicit_iterate", precision_, 13, kImplicitReduceWorkgroup)),
      setup_pass_(make_pass(device_, "implicit_setup", precision_, 13, kImplicitReduceWorkgroup)),
      obstacle_contacts_pass_(
          shader_pipeline(device_, "obstacle_contacts", precision_, 17, sizeof(ObstaclePassConstants))),
      obstacle_elements_pass_(shader_pipeline(device_, "obstacle_energy_elements", precision_, 25,
                                              sizeof(ObstacleElementConstants), kReduceWorkgroup)),
      events_pass_(shader_pipeline(device_, "implicit_events", precision_, 17, sizeof(EventElementConstants),
                                   kImplicitReduceWorkgroup)),
      obstacle_input_(device_, kControlReals * real_size(precision_), Memory::host_visible),
      colliders_input_(device_, 16, Memory::host_visible) {
  CLOTHSIM_ASSERT(settings.cg_max_iterations >= 1, "at least one CG iteration");
  const LatticeCounts counts = element_counts(model);
  // The obstacles' arrays as placeholders; prepare_obstacles() sizes them for the colliders.
  const std::array<std::uint64_t, array_count> bytes = array_bytes(counts, precision_, anchor_capacity_, 0, false);
  arrays_.reserve(array_count);
  for (std::uint32_t a = 0; a < array_count; ++a) arrays_.emplace_back(device_, bytes[a], Memory::device_local);
  if (DeviceMultigrid::applies(counts, settings)) {
    multigrid_.emplace(device_, static_cast<std::uint32_t>(counts.rows), static_cast<std::uint32_t>(counts.cols),
                       connectors_, precision_, settings.cg_line_smoother);
  }
  if (StateChecksPass::runs_on(device_)) {
    state_checks_.emplace(device_, precision_, counts, DeviceForcePath::general);
    using F = DeviceForces;
    state_checks_->bind_elements({&forces_.buffer(F::position)}, {&forces_.buffer(F::velocity)}, forces_);
  }
  // The warm start of the first solve: no velocity change; nothing slipped.
  upload(device_, arrays_[solution], real_bytes(std::vector<double>(3 * std::size_t{particles_}, 0.0), precision_));
  upload(device_, arrays_[slipped], index_bytes<std::uint32_t>(std::vector<std::uint32_t>(particles_, 0u)));
  prepare_obstacles();
  bind_passes();
  record_buffers();
}

DeviceImplicitEuler::~DeviceImplicitEuler() { release_buffers(); }

void DeviceImplicitEuler::bind_passes() {
  const auto bind = [&](ComputePipeline& pipeline, std::initializer_list<const Buffer*> buffers) {
    pipeline.bind(std::vector<const Buffer*>(buffers));
  };
  const auto own = [&](Array a) { return &arrays_[a]; };
  const auto shared = [&](DeviceForces::Array a) { return &forces_.buffer(a); };
  using F = DeviceForces;
  bind(linearize_pass_, {shared(F::position), shared(F::velocity), shared(F::connector_particles),
                         shared(F::connector_rest_length), shared(F::connector_stiffness), shared(F::connector_damping),
                         shared(F::connector_active), shared(F::radial_particles), shared(F::radial_rest_angle),
                         shared(F::radial_stiffness), shared(F::radial_damping), shared(F::radial_fade_length),
                         shared(F::radial_active), own(connector_factors), own(radial_factors)});
  bind(product_pass_,
       {own(direction), shared(F::connector_particles), shared(F::radial_particles), own(connector_factors),
        own(radial_factors), own(solve_real), own(solve_uint), shared(F::slot_force)});
  bind(gather_pass_, {shared(F::gather_offset),
                      shared(F::gather_slot),
                      shared(F::slot_force),
                      shared(F::particle_mass),
                      shared(F::environment),
                      shared(F::force),
                      own(particle_anchor),
                      own(rhs),
                      own(solution),
                      own(residual),
                      own(preconditioned),
                      own(direction),
                      own(product),
                      own(jacobi),
                      own(block_sums),
                      own(solve_real),
                      own(solve_uint),
                      own(hold),
                      own(surface_contacts),
                      own(impulse)});
  bind(diagonal_pass_, {shared(F::gather_offset), shared(F::gather_slot), own(connector_factors), own(radial_factors),
                        shared(F::particle_mass), shared(F::environment), own(particle_anchor), own(solve_real),
                        own(jacobi), own(surface_contacts), own(hold), own(slipped), shared(F::force),
                        shared(F::velocity), own(solution), own(impulse), own(solve_uint)});
  bind(reduce_pass_, {own(block_sums), own(solve_real), own(solve_uint)});
  bind(iterate_pass_, {own(solution), own(residual), own(preconditioned), own(direction), own(product), own(jacobi),
                       own(particle_anchor), own(block_sums), own(solve_real), own(solve_uint), own(hold),
                       own(surface_contacts), own(rhs)});
  bind(setup_pass_, {shared(F::position), shared(F::velocity), shared(F::force), shared(F::particle_mass),
                     shared(F::environment), own(particle_anchor), own(anchor_rows), own(solution), own(direction),
                     shared(F::damping_power), own(block_sums), own(solve_real), own(solve_uint)});
  bind_obstacle_passes();
  bind_event_passes();
  if (multigrid_) {
    multigrid_->bind(MultigridInputs{shared(F::gather_offset), shared(F::gather_slot), shared(F::connector_particles),
                                     shared(F::radial_particles), shared(F::particle_mass), shared(F::environment),
                                     own(connector_factors), own(radial_factors), own(particle_anchor), own(hold),
                                     own(surface_contacts), own(jacobi), own(residual), own(preconditioned),
                                     own(solve_real), own(solve_uint)});
  }
}

std::uint32_t DeviceImplicitEuler::workgroups() const { return reduce_workgroups(particles_); }

ImplicitPassConstants DeviceImplicitEuler::constants(std::uint32_t phase) const {
  return ImplicitPassConstants{particles_,
                               connectors_,
                               radials_,
                               2 * connectors_,
                               phase,
                               workgroups(),
                               connectors_ + radials_,
                               (options_.terms & kSpringDamping) != 0 ? 1u : 0u,
                               0u};
}

void DeviceImplicitEuler::dispatch(VkCommandBuffer commands, const ComputePipeline& pass, std::uint32_t phase,
                                   std::uint32_t invocations, bool iteration) const {
  ImplicitPassConstants pass_constants = constants(phase);
  pass_constants.iteration = iteration ? 1u : 0u;
  pass.dispatch(commands, &pass_constants, invocations);
}

void DeviceImplicitEuler::record_iterations(VkCommandBuffer commands, bool vcycle, std::uint32_t iterations) const {
  for (std::uint32_t i = 0; i < iterations; ++i) {
    dispatch(commands, product_pass_, kProductSystem, connectors_ + radials_, true);
    dispatch(commands, gather_pass_, kGatherProduct, particles_, true);
    dispatch(commands, reduce_pass_, kReduceCurvature, kImplicitReduceWorkgroup);
    if (vcycle) {
      dispatch(commands, iterate_pass_, kIterateAdvance, particles_);
      multigrid_->record_apply(commands, true);
      dispatch(commands, iterate_pass_, kIterateSums, particles_);
    } else {
      dispatch(commands, iterate_pass_, kIterateUpdate, particles_);
    }
    dispatch(commands, reduce_pass_, kReduceResidual, kImplicitReduceWorkgroup);
    dispatch(commands, iterate_pass_, kIterateDirection, particles_);
  }
  record_readback(commands, arrays_[solve_uint], uint_output_, kSolveUints * 4);
}

void DeviceImplicitEuler::record_solve_readback(VkCommandBuffer commands) const {
  record_readback(commands, arrays_[solve_uint], uint_output_, kSolveUints * 4);
  record_readback(commands, arrays_[solve_real], real_output_, kSolveReals * real_size(precision_));
}

void DeviceImplicitEuler::record_solution_product(VkCommandBuffer commands) const {
  dispatch(commands, setup_pass_, kSetupWarmStart, particles_);
  dispatch(commands, product_pass_, kProductSystem, connectors_ + radials_);
}

void DeviceImplicitEuler::record_first_residual(VkCommandBuffer commands, bool vcycle) const {
  record_solution_product(commands);
  dispatch(commands, gather_pass_, kGatherResidual, particles_);
  if (vcycle) {
    multigrid_->record_apply(commands, false);
    dispatch(commands, iterate_pass_, kIterateStart, particles_);
  }
  dispatch(commands, reduce_pass_, kReduceStart, kImplicitReduceWorkgroup);
}

void DeviceImplicitEuler::record_surface_impulses(VkCommandBuffer commands) const {
  record_solution_product(commands);
  dispatch(commands, gather_pass_, kGatherImpulse, particles_);
}

VkCommandBuffer DeviceImplicitEuler::record_timed(std::uint32_t marks,
                                                  const std::function<void(VkCommandBuffer, PassTimer&)>& record) {
  auto timer = std::make_unique<PassTimer>(device_, marks);
  const VkCommandBuffer commands = device_.record([&](VkCommandBuffer c) {
    timer->begin(c);
    record(c, *timer);
  });
  timers_.emplace(commands, std::move(timer));
  return commands;
}

void DeviceImplicitEuler::submit(VkCommandBuffer commands) {
  // The device's time per part from the passes' timestamps; "device steps" is the rest of the wait
  // (the submission, the read-backs after the last mark).
  const Stopwatch wait;
  device_.run(commands);
  const double waited = wait.seconds();
  const PassTimer& timer = *timers_.at(commands);
  timer.add_to(profile_);
  profile_.add(StepStage::device_steps, std::max(0.0, waited - timer.last_seconds()));
}

// Each buffer's passes marked by the CPU's parts of the step (core/step_profile.h): the element
// Jacobians; the assembly (the right-hand side, block Jacobi's inverted blocks and level 0 of the
// V-cycle); the preconditioner's setup (the V-cycle's coarse levels and factor); the linear solve
// (the conjugate gradients with their preconditioner, and the release of held particles); the
// update of the state and the step's end forces.
void DeviceImplicitEuler::record_buffers() {
  const std::uint32_t elements = connectors_ + radials_;
  forces_commands_ = record_timed(1, [&](VkCommandBuffer commands, PassTimer& timer) {
    forces_.record_forces(commands);
    timer.mark(commands, StepStage::forces);
  });
  prepare_commands_ = record_timed(3, [&](VkCommandBuffer commands, PassTimer& timer) {
    record_upload(commands, real_input_, arrays_[solve_real], real_input_.bytes());
    record_upload(commands, uint_input_, arrays_[solve_uint], uint_input_.bytes());
    record_upload(commands, anchor_input_, arrays_[anchor_rows], anchor_input_.bytes());
    // The step's start, from which the obstacle pass after it sweeps.
    if (obstacle_pass_) {
      record_copy(commands, forces_.buffer(DeviceForces::position), arrays_[start_position],
                  arrays_[start_position].bytes());
    }
    timer.mark(commands, StepStage::device_transfers);
    dispatch(commands, linearize_pass_, 0, elements);
    timer.mark(commands, StepStage::jacobians);
    dispatch(commands, setup_pass_, kSetupDisplacement, particles_);
    dispatch(commands, product_pass_, kProductStiffness, elements);
    dispatch(commands, gather_pass_, kGatherRightHandSide, particles_);
    dispatch(commands, diagonal_pass_, kDiagonalHold, particles_);
    if (multigrid_) multigrid_->record_assemble(commands);
    timer.mark(commands, StepStage::assembly);
    if (multigrid_) record_readback(commands, arrays_[solve_uint], uint_output_, kSolveUints * 4);
  });
  for (const bool vcycle : {false, true}) {
    if (vcycle && !multigrid_) continue;
    first_commands_[vcycle] = record_timed(2, [&](VkCommandBuffer commands, PassTimer& timer) {
      if (vcycle) {
        multigrid_->record_setup(commands);
        timer.mark(commands, StepStage::preconditioner_setup);
      }
      record_first_residual(commands, vcycle);
      record_iterations(commands, vcycle, kFirstIterations);
      timer.mark(commands, StepStage::linear_solve);
    });
    // After a release the held set is another: the V-cycle's levels again.
    restart_commands_[vcycle] = record_timed(4, [&](VkCommandBuffer commands, PassTimer& timer) {
      record_upload(commands, uint_input_, arrays_[solve_uint], uint_input_.bytes());
      timer.mark(commands, StepStage::device_transfers);
      if (vcycle) {
        multigrid_->record_assemble(commands);
        timer.mark(commands, StepStage::assembly);
        multigrid_->record_setup(commands);
        timer.mark(commands, StepStage::preconditioner_setup);
      }
      record_first_residual(commands, vcycle);
      record_iterations(commands, vcycle, kFirstIterations);
      timer.mark(commands, StepStage::linear_solve);
    });
    iteration_commands_[vcycle] = record_timed(1, [&](VkCommandBuffer commands, PassTimer& timer) {
      record_iterations(commands, vcycle, kMoreIterations);
      timer.mark(commands, StepStage::linear_solve);
    });
  }
  release_commands_ = record_timed(1, [&](VkCommandBuffer commands, PassTimer& timer) {
    record_surface_impulses(commands);
    dispatch(commands, diagonal_pass_, kDiagonalRelease, particles_);
    timer.mark(commands, StepStage::linear_solve);
    record_readback(commands, arrays_[solve_uint], uint_output_, kSolveUints * 4);
  });
  // The final impulses, for the obstacle pass's friction and their work.
  impulse_commands_ = record_timed(1, [&](VkCommandBuffer commands, PassTimer& timer) {
    record_surface_impulses(commands);
    timer.mark(commands, StepStage::linear_solve);
  });
  end_commands_ = record_timed(3, [&](VkCommandBuffer commands, PassTimer& timer) {
    dispatch(commands, setup_pass_, kSetupCheck, particles_);
    dispatch(commands, setup_pass_, kSetupUpdate, particles_);
    timer.mark(commands, StepStage::solution_update);
    forces_.record_forces(commands);
    timer.mark(commands, StepStage::forces);
    dispatch(commands, setup_pass_, kSetupPowers, particles_);
    dispatch(commands, reduce_pass_, kReducePowers, kImplicitReduceWorkgroup);
    timer.mark(commands, StepStage::solution_update);
    record_solve_readback(commands);
  });
  if (obstacle_pass_) record_obstacle_buffers();
  record_event_buffers();
}

void DeviceImplicitEuler::release_buffers() {
  const auto release = [&](VkCommandBuffer& commands) {
    if (commands != VK_NULL_HANDLE) device_.release(commands);
    commands = VK_NULL_HANDLE;
  };
  for (VkCommandBuffer* commands :
       {&forces_commands_, &prepare_commands_, &end_commands_, &release_commands_, &impulse_commands_,
        &contacts_commands_, &obstacle_commands_, &booking_commands_, &events_commands_}) {
    release(*commands);
  }
  for (std::array<VkCommandBuffer, 2>* buffers : {&first_commands_, &iteration_commands_, &restart_commands_}) {
    for (VkCommandBuffer& commands : *buffers) release(commands);
  }
  timers_.clear();
}

std::uint32_t DeviceImplicitEuler::output_uint(std::uint32_t slot) const {
  std::uint32_t value = 0;
  std::memcpy(&value, uint_output_.mapped() + 4 * std::size_t{slot}, 4);
  return value;
}

double DeviceImplicitEuler::output_real(std::uint32_t slot) const {
  return load_real(real_output_.mapped(), slot, precision_);
}

void DeviceImplicitEuler::write_step(double h, double end_time) {
  if (model_.anchors.size() > anchor_capacity_) {
    // More anchors than the rows hold (pins added at run time): larger arrays, bound and recorded anew.
    anchor_capacity_ = 2 * static_cast<std::uint32_t>(model_.anchors.size());
    const std::uint64_t bytes = std::uint64_t{anchor_capacity_} * kAnchorRowReals * real_size(precision_);
    arrays_[anchor_rows] = Buffer(device_, bytes, Memory::device_local);
    anchor_input_ = Buffer(device_, bytes, Memory::host_visible);
    release_buffers();
    bind_passes();
    record_buffers();
  }
  // Written in place into the staging the step's first submission copies from: no allocation.
  std::byte* reals = real_input_.mapped();
  for (std::uint32_t slot = 0; slot < kSolveReals; ++slot) store_real(reals, slot, 0.0, precision_);
  store_real(reals, kImplicitStep, h, precision_);
  store_real(reals, kStiffnessScale, h * h, precision_);
  store_real(reals, kDampingScale, h, precision_);
  store_real(reals, kRelativeResidual, settings_.cg_tolerance, precision_);
  store_real(reals, kEventHardening, model_.limits.hardening, precision_);
  store_real(reals, kEventTime, end_time, precision_);
  write_solve_counters();
  // Each anchor's path at the step's end: where its particle ends, how fast, and the acceleration
  // its power is taken with (ImplicitEuler::evaluate at the end).
  std::byte* rows = anchor_input_.mapped();
  std::size_t index = 0;
  for (const Anchor& anchor : model_.anchors) {
    for (const Vec3& v :
         {anchor.path.position(end_time), anchor.path.velocity_at(end_time), anchor.path.acceleration(end_time)}) {
      for (double component : {v.x, v.y, v.z}) store_real(rows, index++, component, precision_);
    }
  }
}

void DeviceImplicitEuler::write_solve_counters() {
  std::array<std::uint32_t, kSolveUints> uints{};
  uints[kSolveConverged] = 1;
  uints[kMaxIterations] = static_cast<std::uint32_t>(settings_.cg_max_iterations);
  uints[kNonFiniteParticle] = kNoParticle;
  uints[kHolding] = holding_ ? 1 : 0;
  std::memcpy(uint_input_.mapped(), uints.data(), sizeof uints);
}

bool DeviceImplicitEuler::choose_vcycle() const {
  if (!multigrid_) return false;
  const float ratio = std::bit_cast<float>(output_uint(kStiffnessRatio));
  return vcycle_pays(jacobi_iterations_estimate(ratio, model_.rows, model_.cols), settings_.cg_vcycle_threshold);
}

int DeviceImplicitEuler::solve(VkCommandBuffer first) {
  submit(first);
  while (output_uint(kSolveDone) == 0) submit(iteration_commands_[vcycle_]);
  const int iterations = static_cast<int>(output_uint(kIterations));
  if (output_uint(kSolveConverged) == 0) ++stats_.cg_unconverged_solves;
  return iterations;
}

std::uint32_t DeviceImplicitEuler::take_step(double h, double end_time) {
  if (!forces_current_) {
    // f0 at the state the host uploaded (the steps' ends evaluate it themselves).
    submit(forces_commands_);
    if (!uncounted_evaluation_) ++stats_.force_evaluations;
    uncounted_evaluation_ = false;
    forces_current_ = true;
  }
  write_step(h, end_time);
  submit(prepare_commands_);
  vcycle_ = choose_vcycle();
  last_iterations_ = solve(first_commands_[vcycle_]);
  if (holding_) {
    // A surface cannot pull: let go of the particles it would have to, and solve again for them.
    submit(release_commands_);
    if (output_uint(kReleased) != 0) {
      write_solve_counters();
      last_iterations_ += solve(restart_commands_[vcycle_]);
    }
    submit(impulse_commands_);
  }
  submit(end_commands_);
  ++stats_.force_evaluations;
  stats_.cg_iterations += static_cast<std::uint64_t>(last_iterations_);
  stats_.cg_max_iterations_in_a_step =
      std::max(stats_.cg_max_iterations_in_a_step, static_cast<std::uint64_t>(last_iterations_));
  return output_uint(kNonFiniteParticle);
}

// Steps as named stages: what changed goes up, each step runs on the device with the host reading
// only the solve's counters (and with obstacles the pass's sums), the work integrals are booked
// from the step's end powers, and the state comes back once.
StepOutcome DeviceImplicitEuler::run(ClothState& state, double t_limit, std::uint32_t max_steps) {
  CLOTHSIM_ASSERT(t_limit > state.time, "step() needs a limit after the current time");
  {
    StageTimer timer(profile_, StepStage::device_transfers);
    upload_changes(state);
  }
  if (prepare_obstacles()) {
    release_buffers();
    bind_passes();
    record_buffers();
  }
  const double t0 = state.time;  // the colliders' paths are written relative to it
  if (obstacle_pass_) begin_obstacles(t0);
  if (runs_self_contacts()) begin_self_contacts();
  StepOutcome outcome{StepStatus::ok, 0.0, 0, false};
  std::uint32_t steps = 0;
  while (state.time < t_limit && (max_steps == 0 || steps < max_steps)) {
    // An impact ahead on an obstacle limits the step, as the collision stage does on the CPU.
    const double limit = obstacle_pass_ ? std::min(t_limit, step_limit_) : t_limit;
    bool clipped = false;
    const double h = clip_step(state.time, settings_.time_step, limit, clipped);
    const double end_time = clipped ? limit : state.time + h;
    const std::uint32_t failed = take_step(h, end_time);
    outcome.step = h;
    if (failed != kNoParticle) {
      // The device's state is the step's start; the next solve starts from no velocity change.
      upload(device_, arrays_[solution], real_bytes(std::vector<double>(3 * std::size_t{particles_}, 0.0), precision_));
      outcome = {StepStatus::non_finite, h, failed, true};
      break;
    }
    // Work integrals with the end-of-step powers (backward Euler quadrature), as on the CPU.
    state.damping_work += h * output_real(kDampingPower);
    state.drag_work += h * output_real(kDragPower);
    state.anchor_work += h * output_real(kAnchorPower);
    const double start_time = state.time;
    state.time = end_time;
    if (obstacle_pass_) resolve_obstacles(state, start_time - t0, end_time - t0);
    if (runs_spring_events()) apply_spring_events(state);
    record_accepted_step(h);
    ++steps;
  }
  StageTimer timer(profile_, StepStage::device_transfers);
  read_state(state);
  return outcome;
}

}  // namespace clothsim::gpu
