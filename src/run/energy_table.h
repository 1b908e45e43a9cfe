// energy.csv: one row per frame written, its columns named in the header line (docs/cli.md,
// "energy.csv"). The columns are a format that readers index by name and position, so they are
// listed here once, in the file's order, and the header and every row come from this one list;
// the values come from the records of sim/statistics.h and integrators/integrator.h. A field
// added to a record reaches summary.json, checkpoints and the Python module by itself and
// energy.csv by a line here.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

#include "core/record_fields.h"
#include "integrators/integrator.h"
#include "sim/simulation.h"
#include "sim/statistics.h"

namespace clothsim {

struct EnergyRow {
  std::uint64_t frame = 0;  // 0: the initial state
  double time = 0.0;        // s
  EnergyBalance balance;
  IntegratorStats stats;
  ModelChanges changes;
  ContactStatistics contacts;

  // The simulation now, as frame `frame`.
  static EnergyRow of(std::uint64_t frame, const Simulation& simulation);

  template <typename Self, typename Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit("frame", self.frame);
    visit("time", self.time);
    EnergyReport::for_each_field(self.balance.energy, visit);
    visit("total", Computed<double>{self.balance.energy.total()});
    visit("damping_work", self.balance.damping_work);
    visit("drag_work", self.balance.drag_work);
    visit("anchor_work", self.balance.anchor_work);
    visit("balance_error", Computed<double>{self.balance.error()});
    visit("accepted_steps", self.stats.accepted_steps);
    visit("rejected_steps", self.stats.rejected_steps);
    visit("broken_connectors", self.changes.broken_connectors);
    visit("max_plastic_strain", self.changes.max_plastic_strain);
    visit("max_rest_angle_change", self.changes.max_rest_angle_change);
    visit("plastic_work", self.balance.plastic_work);
    visit("fracture_work", self.balance.fracture_work);
    visit("contact_work", self.balance.contact_work);
    visit("contacts", self.contacts.contacts);
    visit("self_contacts", self.contacts.self_contacts);
  }
};

// The header line, without its newline: the column names, comma-separated.
std::string energy_table_header();
// One row, without its newline: integers in decimal, reals with 17 significant digits (%.17g),
// which read back to the same double.
std::string energy_table_row(const EnergyRow& row);

}  // namespace clothsim
