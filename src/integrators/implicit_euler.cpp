#include "integrators/implicit_euler.h"

#include <algorithm>
#include <cmath>

#include "core/assert.h"
#include "core/parallel.h"
#include "core/step_profile.h"
#include "integrators/dynamics.h"

namespace clothsim {

ImplicitEuler::ImplicitEuler(const ClothModel& model, const IntegratorSettings& settings, const ForceOptions& options)
    : model_(model),
      settings_(settings),
      options_(options),
      threads_(options.threads),
      system_(model, settings, options.threads, profile_) {
  CLOTHSIM_ASSERT(settings.cg_max_iterations >= 1, "at least one CG iteration");
  CLOTHSIM_ASSERT(options.precision == Precision::float64,
                  "implicit Euler's forces are float64 (sim/backend.h refuses float32 with it)");
  const std::size_t n = model.particle_count();
  buffers_.resize(model);
  force_.resize(n);
  evaluated_position_.resize(n);
  evaluated_velocity_.resize(n);
  revision_ = model.revision;
  displacement_.assign(n, Vec3{});
  slipped_.assign(n, 0);
}

std::size_t ImplicitEuler::workspace_bytes() const {
  const auto bytes = [](const auto& vector) { return vector.capacity() * sizeof(vector[0]); };
  std::size_t total = buffers_.bytes() + system_.bytes();
  total += bytes(force_) + bytes(evaluated_position_) + bytes(evaluated_velocity_);
  total += bytes(displacement_) + bytes(slipped_);
  return total;
}

std::size_t ImplicitEuler::workspace_bytes_for(const LatticeCounts& counts, const IntegratorSettings& settings) {
  const std::size_t n = counts.particles;
  std::size_t total = BlockSystem::bytes_for(counts, settings);
  total += 4 * n * sizeof(Vec3);  // forces, the state they were evaluated at, the displacement
  total += n * sizeof(std::uint8_t);  // slipped
  return total;
}

ImplicitEuler::Powers ImplicitEuler::evaluate(double time, std::span<const Vec3> position,
                                              std::span<const Vec3> velocity) {
  StageTimer timer(profile_, StepStage::forces);
  ++stats_.force_evaluations;
  const ForcePowers powers = evaluate_forces(model_, position, velocity, options_.terms, threads_, buffers_, force_);
  Powers out{powers.damping, powers.drag, 0.0};
  // The power of the force each anchor exerts to keep its particle on the path, m a - f (as in
  // ClothDynamics::evaluate).
  for (const Anchor& anchor : model_.anchors) {
    const std::uint32_t p = anchor.particle;
    out.anchor += dot(velocity[p], model_.particle_mass[p] * anchor.path.acceleration(time) - force_[p]);
  }
  std::copy(position.begin(), position.end(), evaluated_position_.begin());
  std::copy(velocity.begin(), velocity.end(), evaluated_velocity_.begin());
  evaluated_time_ = time;
  evaluated_valid_ = true;
  return out;
}

void ImplicitEuler::form_rhs(double h) {
  parallel_for(model_.particle_count(), threads_, [&](std::size_t p) {
    Vec3& rhs = system_.rhs[p];
    rhs = system_.free[p] ? h * (force_[p] - rhs) : Vec3{};
  });
}

int ImplicitEuler::solve() {
  const BlockSystem::Solve result = system_.solve(settings_.cg_tolerance, 0.0, settings_.cg_max_iterations);
  if (!result.converged) ++stats_.cg_unconverged_solves;
  return result.iterations;
}

StepOutcome ImplicitEuler::step(ClothState& state, double t_limit) {
  CLOTHSIM_ASSERT(t_limit > state.time, "step() needs a limit after the current time");
  const std::size_t n = model_.particle_count();
  bool clipped = false;
  const double h = clip_step(state.time, settings_.time_step, t_limit, clipped);
  const double end_time = clipped ? t_limit : state.time + h;

  // A model edit between steps (an anchor released, a spring broken or yielded) changes which
  // particles are integrated and the forces of the previous step's end.
  if (model_.revision != revision_) {
    system_.update_free();
    evaluated_valid_ = false;
    revision_ = model_.revision;
  }
  // f0: reuse the forces of the previous step's end when the state and the model are still those.
  const bool reusable = evaluated_valid_ && evaluated_time_ == state.time &&
                        std::equal(state.position.begin(), state.position.end(), evaluated_position_.begin()) &&
                        std::equal(state.velocity.begin(), state.velocity.end(), evaluated_velocity_.begin());
  if (!reusable) evaluate(state.time, state.position, state.velocity);

  system_.compute_jacobians(options_.terms, state.position, state.velocity);
  parallel_for(n, threads_, [&](std::size_t p) {
    if (system_.free[p]) displacement_[p] = h * state.velocity[p];
  });
  for (const Anchor& anchor : model_.anchors) {
    const std::uint32_t p = anchor.particle;
    displacement_[p] = anchor.path.position(end_time) - state.position[p];
    system_.solution[p] = anchor.path.velocity_at(end_time) - state.velocity[p];
  }
  // A = M + h C + h^2 K, and K z into the right-hand side, which form_rhs completes.
  system_.assemble(options_.terms, h, h * h, displacement_, system_.rhs);
  form_rhs(h);
  hold_on_surfaces(state, h);
  system_.setup_preconditioner();
  last_iterations_ = solve();
  if (release_held_particles()) {
    // The multigrid's levels are built for the held set; the aggregates' coarse matrix keeps the
    // first one (the additive correction stays definite with any).
    if (system_.uses_multigrid()) system_.setup_preconditioner();
    last_iterations_ += solve();
  }
  stats_.cg_iterations += static_cast<std::uint64_t>(last_iterations_);
  stats_.cg_max_iterations_in_a_step =
      std::max(stats_.cg_max_iterations_in_a_step, static_cast<std::uint64_t>(last_iterations_));

  std::vector<Vec3>& dv = system_.solution;
  for (std::size_t p = 0; p < n; ++p) {
    if (system_.free[p] && !is_finite(dv[p])) {
      // Leave the state as it was: the caller keeps the last good state.
      std::fill(dv.begin(), dv.end(), Vec3{});
      return {StepStatus::non_finite, h, static_cast<std::uint32_t>(p), true};
    }
  }
  parallel_for(n, threads_, [&](std::size_t p) {
    if (!system_.free[p]) return;
    state.velocity[p] += dv[p];
    state.position[p] += h * state.velocity[p];
  });
  for (const Anchor& anchor : model_.anchors) {
    state.position[anchor.particle] = anchor.path.position(end_time);
    state.velocity[anchor.particle] = anchor.path.velocity_at(end_time);
  }
  state.time = end_time;
  book_surface_impulses(state);

  // Work integrals with the end-of-step powers (backward Euler quadrature).
  const Powers powers = evaluate(state.time, state.position, state.velocity);
  state.damping_work += h * powers.damping;
  state.drag_work += h * powers.drag;
  state.anchor_work += h * powers.anchor;

  record_accepted_step(h);
  return {StepStatus::ok, h, 0, false};
}

void ImplicitEuler::transfer_state(StateArchive& archive) {
  Integrator::transfer_state(archive);
  archive.array("implicit_euler.dv", system_.solution);
  archive.array("implicit_euler.slipped", slipped_);
  // The forces of the last step's end, which the next step reuses (advance): restored with what
  // they were computed at, so that a resumed run evaluates exactly what the uninterrupted one does
  // (summary.json's force_evaluations included).
  archive.array("implicit_euler.evaluated_force", force_);
  archive.array("implicit_euler.evaluated_position", evaluated_position_);
  archive.array("implicit_euler.evaluated_velocity", evaluated_velocity_);
  archive.value("implicit_euler.evaluated_time", evaluated_time_);
  archive.value("implicit_euler.evaluated_valid", evaluated_valid_);
  archive.value("implicit_euler.model_revision", revision_);
  // Which particles are integrated follows the restored model (the next model change moves them again).
  if (archive.loading()) system_.update_free();
}

}  // namespace clothsim
