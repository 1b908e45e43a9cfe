// Symplectic (semi-implicit) Euler: v' = v + h a(x, v), x' = x + h v'. First order, one force
// evaluation per step, and for conservative forces it keeps energy bounded instead of drifting,
// which makes it the usual choice in games. Fixed step.
#pragma once

#include "integrators/dynamics.h"
#include "integrators/integrator.h"

namespace clothsim {

class SymplecticEuler final : public Integrator {
 public:
  SymplecticEuler(const ClothModel& model, const IntegratorSettings& settings, const ForceOptions& options);
  IntegratorKind kind() const override { return IntegratorKind::symplectic_euler; }
  StepOutcome step(ClothState& state, double t_limit) override;
  std::size_t workspace_bytes() const override { return dynamics_.bytes() + rate_.bytes(); }
  // The bytes workspace_bytes() reports for `particles` particles, besides the force buffers
  // (ForceBuffers::bytes_for) (sim/memory_estimate.h).
  static std::size_t workspace_bytes_for(std::size_t particles) { return StateDerivative::bytes_for(particles); }

 private:
  const ClothModel& model_;
  IntegratorSettings settings_;
  ClothDynamics dynamics_;
  StateDerivative rate_;
};

}  // namespace clothsim
