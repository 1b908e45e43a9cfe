// Simulation::transfer_state: what a checkpoint holds of a simulation (sim/simulation.h), in one
// list that saves and restores (core/state_archive.h).
#include <stdexcept>
#include <string>

#include "core/record_fields.h"
#include "model/model_state.h"
#include "sim/simulation.h"

namespace clothsim {

void Simulation::transfer_state(StateArchive& archive) {
  checked_energy_.reset();
  if (!archive.loading() && failure_) {
    throw std::logic_error("a failed simulation is not saved: its state is the last good one, not one to go on from");
  }
  // The state.
  archive.value("time", state_.time);
  archive.array("position", state_.position);
  archive.array("velocity", state_.velocity);
  archive.value("damping_work", state_.damping_work);
  archive.value("drag_work", state_.drag_work);
  archive.value("anchor_work", state_.anchor_work);
  archive.value("plastic_work", state_.plastic_work);
  archive.value("fracture_work", state_.fracture_work);
  archive.value("contact_work", state_.contact_work);
  archive.value("edit_work", edit_work_);

  // The model as the run has changed it; a restored model gets a new integrator, which then takes
  // the saved one's controller state.
  transfer_model_changes(archive, *model_);
  if (archive.loading()) {
    // On the run's backend and precision: a Vulkan run resumes on its device.
    integrator_ = new_integrator();
  }
  integrator_->transfer_state(archive);
  transfer_fields(archive, "retired", retired_stats_);
  precision_choice_.transfer_state(archive);

  // The energy balance's reference and the blow-up check's scale.
  archive.value("initial_energy", initial_energy_);
  transfer_fields(archive, "initial_report", initial_report_);
  archive.value("energy_scale", energy_scale_);
  archive.value("released", released_);
  archive.value("moved_work", moved_work_);
  archive.array("last_works", last_works_);

  // Counts over the run.
  transfer_fields(archive, "events", event_totals_);
  transfer_fields(archive, "contacts", contact_statistics_);

  if (archive.loading()) {
    // The stages' scratch and caches start afresh from the restored model: both rebuild what
    // they keep between steps from the model and the state (their results do not depend on it).
    *collision_stage_ = CollisionStage{};  // the same object: the integrator points into it
    spring_events_ = SpringEvents{};
    failure_.reset();
    check_state();
  }
}

}  // namespace clothsim
