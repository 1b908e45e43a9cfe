// Simulation: owns a model, its state and an integrator, and advances to requested times.
//
// advance_to(t) reads like the algorithm it runs:
//   while the state is before t:
//     integrator step (adaptive, never past t)   -> StepProfile::integration / forces
//     discrete events between steps               -> (tearing, plasticity: later issues)
//     check the state: finite, not exploding      -> StepProfile::checks
// sim/profile.h turns the profile into the table `clothsim run --profile` prints.
// A failed check or integrator stops the simulation with a Diagnosis (time, step, element), and
// the state stays at the last good step, so a caller can still write what it has.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "forces/forces.h"
#include "integrators/integrator.h"
#include "model/cloth_model.h"

namespace clothsim {

struct SimulationSettings {
  IntegratorSettings integrator;
  int threads = 0;  // 0: choose from the lattice size and the idle cores (core/parallel.h)
  ForceTerms terms = kAllForceTerms;
  ForceKernel kernel = ForceKernel::automatic;  // which force implementation (forces.h)
  // A connector longer than this many times its rest length means the integration has blown up.
  double explosion_stretch = 1000.0;
};

// Wall time per phase, s. The integrator's own sub-phases (stage sums, error control, ...) are
// in Simulation::integration_phases().
struct StepProfile {
  double forces = 0.0;       // force evaluation (inside the integrator)
  double integration = 0.0;  // the rest of the integrator: stage sums, error control
  double checks = 0.0;       // finiteness and explosion checks
};

struct Diagnosis {
  double time = 0.0;           // s, of the last good state
  std::uint64_t step = 0;      // accepted steps before the failure
  std::string element;         // "particle 37 (row 1, col 16)", "connector 12 between ..."
  std::string message;         // the whole explanation, naming time, step and element
};

// Energies and the work done on the sheet; `error()` is how far the run is from the energy
// balance E(t) = E(0) + W_damping + W_drag + W_anchor, which the exact flow satisfies.
struct EnergyBalance {
  EnergyReport energy;
  double initial_total = 0.0;
  double damping_work = 0.0;
  double drag_work = 0.0;
  double anchor_work = 0.0;
  double error() const { return energy.total() - (initial_total + damping_work + drag_work + anchor_work); }
};

class Simulation {
 public:
  Simulation(ClothModel model, ClothState initial, const SimulationSettings& settings);

  // Advances to exactly `time` (>= the current time). Returns false if the simulation failed,
  // now or before; failure() then says why, and state() is the last good state.
  bool advance_to(double time);

  const ClothModel& model() const { return *model_; }
  const ClothState& state() const { return state_; }
  const SimulationSettings& settings() const { return settings_; }
  int threads() const { return threads_; }
  const IntegratorStats& integrator_stats() const { return integrator_->stats(); }
  const StepProfile& profile() const { return profile_; }
  // The timed sub-phases of profile().integration, as the integrator reports them.
  std::vector<PhaseTime> integration_phases() const { return integrator_->phase_times(); }
  // Bytes held by the model's arrays, the state and the integrator's workspace (capacity, not
  // just size): the simulation's own memory, without the process around it.
  std::size_t memory_bytes() const;
  const std::optional<Diagnosis>& failure() const { return failure_; }

  EnergyReport energy() const;
  EnergyBalance energy_balance() const;

 private:
  void check_state();
  void fail(std::string element, std::string message);

  std::unique_ptr<ClothModel> model_;  // on the heap: the integrator keeps a reference to it
  ClothState state_;
  SimulationSettings settings_;
  int threads_ = 1;
  std::unique_ptr<Integrator> integrator_;
  double initial_energy_ = 0.0;
  StepProfile profile_;
  std::optional<Diagnosis> failure_;
};

}  // namespace clothsim
