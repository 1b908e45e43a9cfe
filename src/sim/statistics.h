// What a Simulation reports about itself between steps: its energy balance, its contacts, how far
// the sheet has changed, and why it failed. Each record lists its fields once
// (core/record_fields.h), and energy.csv, summary.json, checkpoints, the sweep's index and the
// Python module all take them from there. IntegratorStats (integrators/integrator.h) and
// SpringEventCounts (events/spring_events.h) are the integrator's and the event stage's.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "core/record_fields.h"
#include "forces/forces.h"

namespace clothsim {

// Why a simulation stopped: the last good state's time and step, the element, the explanation.
struct Diagnosis {
  double time = 0.0;       // s, of the last good state
  std::uint64_t step = 0;  // accepted steps before the failure
  std::string element;     // "particle 37 (row 1, col 16)", "connector 12 between ..."
  std::string message;     // the whole explanation, naming time, step and element

  template <typename Self, typename Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit("time", self.time);
    visit("step", self.step);
    visit("element", self.element);
    visit("message", self.message);
  }
};

// Energies and the work done on the sheet; `error()` is how far the run is from the energy
// balance E(t) = E(0) + W_damping + W_drag + W_anchor + W_edit + W_plastic + W_fracture + W_contact,
// which the exact flow satisfies.
struct EnergyBalance {
  EnergyReport energy;
  double initial_total = 0.0;  // E(0), J
  double damping_work = 0.0;   // J (never positive)
  double drag_work = 0.0;      // J (never positive in still air)
  double anchor_work = 0.0;    // work of the anchors moving on their paths and of their velocity jumps, J
  double edit_work = 0.0;      // energy added by live parameter edits between steps (Simulation::set_*), J
  double plastic_work = 0.0;   // elastic energy released by yielding and creasing, J (never positive)
  double fracture_work = 0.0;  // elastic energy released by breaking springs, J (never positive)
  double contact_work = 0.0;   // energy changed by the collision stage, J (never positive against static obstacles)
  double error() const {
    return energy.total() - (initial_total + damping_work + drag_work + anchor_work + edit_work + plastic_work +
                             fracture_work + contact_work);
  }

  // The energy terms and their total, the works of the run and the balance error, then what the
  // balance is measured from.
  template <typename Self, typename Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    EnergyReport::for_each_field(self.energy, visit);
    visit("total", Computed<double>{self.energy.total()});
    visit("damping_work", self.damping_work);
    visit("drag_work", self.drag_work);
    visit("anchor_work", self.anchor_work);
    visit("balance_error", Computed<double>{self.error()});
    visit("plastic_work", self.plastic_work);
    visit("fracture_work", self.fracture_work);
    visit("contact_work", self.contact_work);
    visit("edit_work", self.edit_work);
    visit("initial_total", self.initial_total);
  }
};

// Particles in contact with obstacles and pairs in self-contact (collision/): after the last
// step, and summed over steps.
struct ContactStatistics {
  std::size_t contacts = 0;         // particles in contact after the last accepted step
  std::uint64_t contact_steps = 0;  // sum over accepted steps of the particles in contact
  std::size_t max_in_a_step = 0;    // the most particles in contact after one step
  // Self-collision (collision/self_contacts.h), in pairs of elements.
  std::size_t self_contacts = 0;         // pairs pushed apart after the last accepted step
  std::uint64_t self_contact_steps = 0;  // summed over accepted steps
  std::size_t self_max_in_a_step = 0;    // the most after one step
  std::uint64_t self_impacts = 0;        // pairs whose motion touched, stopped (summed over steps)
  std::uint64_t self_impact_zones = 0;   // impact zones moved as one (summed over steps)
  std::uint64_t self_unresolved = 0;     // pairs left touching after the zones (summed; 0 expected)

  template <typename Self, typename Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit("contacts", self.contacts);
    visit("contact_steps", self.contact_steps);
    visit("max_in_a_step", self.max_in_a_step);
    visit("self_contacts", self.self_contacts);
    visit("self_contact_steps", self.self_contact_steps);
    visit("self_max_in_a_step", self.self_max_in_a_step);
    visit("self_impacts", self.self_impacts);
    visit("self_impact_zones", self.self_impact_zones);
    visit("self_unresolved", self.self_unresolved);
  }
};

// How far the sheet has changed from its built model: the statistics of events/ that
// energy.csv and summary.json report.
struct ModelChanges {
  std::size_t broken_connectors = 0;   // so far
  std::size_t broken_radials = 0;      // so far (each broken connector takes 1 to 3 with it)
  double max_plastic_strain = 0.0;     // max over intact connectors of |L / L_original - 1|
  double max_rest_angle_change = 0.0;  // max over intact radial springs of |theta0 - theta0_original|, rad

  template <typename Self, typename Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit("broken_connectors", self.broken_connectors);
    visit("broken_radials", self.broken_radials);
    visit("max_plastic_strain", self.max_plastic_strain);
    visit("max_rest_angle_change", self.max_rest_angle_change);
  }
};

}  // namespace clothsim
