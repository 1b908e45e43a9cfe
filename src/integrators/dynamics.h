// The ODE right-hand side: y = (x, v, W) -> y' = (v, f(x, v) / m, P), for every integrator.
//
// The position rate is the velocity itself, so a StateDerivative holds only the acceleration and
// the powers: an integrator that needs the position rate of a stage reads (or, like the
// Runge-Kutta driver, rewrites in terms of) that stage's velocity, instead of keeping a copy.
//
// Anchored particles are not integrated: before a stage is evaluated, constrain() puts them at
// their path's exact position and velocity for the stage time, and their derivative is the path's
// velocity and acceleration. W are the three work integrals of ClothState and P their rates
// (damping, drag and anchor power), integrated alongside the motion to the integrator's order.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "forces/forces.h"
#include "integrators/integrator.h"
#include "model/cloth_model.h"

namespace clothsim {

struct StateDerivative {
  std::vector<Vec3> velocity_rate;  // [particle_count()], m/s^2
  double damping_power = 0.0;       // W
  double drag_power = 0.0;          // W
  double anchor_power = 0.0;        // W, power the anchors put into the sheet
  void resize(std::size_t particles);
  std::size_t bytes() const { return velocity_rate.capacity() * sizeof(Vec3); }
  // Bytes one StateDerivative holds for `particles` (the memory estimate, sim/memory_estimate.h).
  static constexpr std::size_t bytes_for(std::size_t particles) { return particles * sizeof(Vec3); }
};

class ClothDynamics {
 public:
  ClothDynamics(const ClothModel& model, const ForceOptions& options);

  // Puts anchored particles at their path's position and velocity at `time`.
  void constrain(double time, std::span<Vec3> position, std::span<Vec3> velocity) const;
  // y' at (time, position, velocity). Anchored particles must already be constrained. The forces
  // are computed into out.velocity_rate and divided by the masses there: no force array of its own.
  void evaluate(double time, std::span<const Vec3> position, std::span<const Vec3> velocity, StateDerivative& out);

  const ClothModel& model() const { return model_; }
  int threads() const { return options_.threads; }
  // The springs' arithmetic (ForceOptions::precision), and whether it can be float32: on the
  // lattice kernel only. set_precision() switches it for the evaluations after it (ForceBuffers::
  // set_precision): `precision: auto`'s choice, frame by frame (sim/precision_choice.h).
  Precision precision() const { return options_.precision; }
  bool runs_float32() const { return buffers_.uses_lattice_kernel(); }
  void set_precision(Precision precision);
  // How far float32 forces are from float64's at (time, position, velocity): evaluates them in
  // float64 into `exact` and in float32 into `rounded` (two evaluations; the precision is then as
  // before), and returns the largest difference of a particle's acceleration, m/s^2 (infinity
  // where one is not finite): their rounding, and where a spring is within float's singular
  // threshold of straight (forces/lattice_spring.h, SingularLimits), float32's other one-sided
  // limit (sim/precision_choice.h).
  double float32_rounding(double time, std::span<const Vec3> position, std::span<const Vec3> velocity,
                          StateDerivative& exact, StateDerivative& rounded);
  std::uint64_t evaluations() const { return evaluations_; }
  double seconds() const { return seconds_; }
  // Bytes of scratch memory held (the force buffers).
  std::size_t bytes() const { return buffers_.bytes(); }

 private:
  const ClothModel& model_;
  ForceOptions options_;
  ForceBuffers buffers_;
  std::uint64_t evaluations_ = 0;
  double seconds_ = 0.0;
};

// Shortens a step so that it lands exactly on t_limit instead of stopping a rounding error short
// of it (step_control::clip_step, integrators/step_control.inc). Returns the step; sets `clipped`
// when the step ends at t_limit.
double clip_step(double time, double step, double t_limit, bool& clipped);

}  // namespace clothsim
