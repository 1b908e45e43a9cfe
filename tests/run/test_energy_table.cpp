// energy.csv's columns (run/energy_table.h): the header and the rows from one list, in the file
// format readers know.
#include <gtest/gtest.h>

#include <string>

#include "run/energy_table.h"

namespace clothsim {
namespace {

TEST(EnergyTable, TheColumnsAreTheFileFormat) {
  // energy.csv's columns as readers have indexed them since they were documented (docs/cli.md):
  // a change here is a change of the file format.
  EXPECT_EQ(energy_table_header(),
            "frame,time,kinetic,gravitational,connector,radial_adjacent,radial_opposite,total,damping_work,drag_work,"
            "anchor_work,balance_error,accepted_steps,rejected_steps,broken_connectors,max_plastic_strain,"
            "max_rest_angle_change,plastic_work,fracture_work,contact_work,contacts,self_contacts");
  EnergyRow row;
  row.frame = 12;
  row.time = 0.1;
  row.balance.energy.kinetic = 1.0 / 3.0;
  row.stats.accepted_steps = 4000000000ull;
  row.contacts.self_contacts = 7;
  const std::string text = energy_table_row(row);
  EXPECT_EQ(text.substr(0, 3), "12,");
  EXPECT_NE(text.find(",0.10000000000000001,0.33333333333333331,"), std::string::npos) << text;
  EXPECT_NE(text.find(",4000000000,0,"), std::string::npos) << text;
  EXPECT_EQ(text.substr(text.rfind(',') + 1), "7");
}

}  // namespace
}  // namespace clothsim
