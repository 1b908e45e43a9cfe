// The records of sim/statistics.h (and IntegratorStats, SpringEventCounts, EnergyReport) and their
// one field list (core/record_fields.h): every member is in the list exactly once, the
// statistics of replaced integrators add up as their Tally says, a checkpoint round trip keeps
// every field.
#include <gtest/gtest.h>

#include <cstddef>
#include <set>
#include <string>
#include <vector>

#include "core/record_fields.h"
#include "events/spring_events.h"
#include "integrators/integrator.h"
#include "sim/statistics.h"

namespace clothsim {
namespace {

// The stored fields' bytes cover the whole record, each member once: a member left out of the
// list (or listed twice) fails. Every field of these records is 8 bytes, so there is no padding.
template <typename Record>
void expect_list_covers_every_member() {
  Record record;
  std::set<const void*> seen;
  std::set<std::string> names;
  std::size_t bytes = 0;
  Record::for_each_field(record, [&](std::string_view name, auto&& field, auto...) {
    EXPECT_TRUE(names.insert(std::string(name)).second) << "two fields named " << name;
    if constexpr (!is_computed_v<decltype(field)>) {
      EXPECT_TRUE(seen.insert(&field).second) << name << " is listed twice";
      bytes += sizeof(field);
    }
  });
  EXPECT_EQ(bytes, sizeof(Record)) << "a member is missing from the field list";
}

TEST(RecordFields, EveryMemberIsListedOnce) {
  expect_list_covers_every_member<EnergyReport>();
  expect_list_covers_every_member<EnergyBalance>();
  expect_list_covers_every_member<IntegratorStats>();
  expect_list_covers_every_member<ContactStatistics>();
  expect_list_covers_every_member<ModelChanges>();
  expect_list_covers_every_member<SpringEventCounts>();
}

TEST(RecordFields, ComputedValuesAreTheRecordsOwn) {
  EnergyBalance balance;
  balance.energy = {1.0, 2.0, 3.0, 4.0, 5.0};
  balance.initial_total = 10.0;
  balance.damping_work = -0.5;
  balance.contact_work = -0.25;
  double total = 0.0;
  double error = 0.0;
  EnergyBalance::for_each_field(balance, [&](std::string_view name, auto&& field, auto...) {
    if (name == "total") total = field_value(field);
    if (name == "balance_error") error = field_value(field);
  });
  EXPECT_EQ(total, 15.0);
  EXPECT_EQ(error, balance.error());
  EXPECT_EQ(error, 15.0 - (10.0 - 0.5 - 0.25));
}

TEST(RecordFields, ReplacedIntegratorsStatisticsAddUpByTheirTally) {
  IntegratorStats earlier;
  earlier.accepted_steps = 10;
  earlier.rejected_steps = 2;
  earlier.force_evaluations = 60;
  earlier.smallest_step = 1e-4;
  earlier.largest_step = 1e-2;
  earlier.last_step = 5e-3;
  earlier.cg_iterations = 40;
  earlier.cg_max_iterations_in_a_step = 9;
  earlier.cg_unconverged_solves = 1;
  IntegratorStats later;
  later.accepted_steps = 5;
  later.rejected_steps = 1;
  later.force_evaluations = 30;
  later.smallest_step = 2e-4;
  later.largest_step = 2e-2;
  later.last_step = 1e-3;
  later.cg_iterations = 7;
  later.cg_max_iterations_in_a_step = 3;
  later.cg_unconverged_solves = 0;
  const IntegratorStats total = combine(earlier, later);
  EXPECT_EQ(total.accepted_steps, 15u);
  EXPECT_EQ(total.rejected_steps, 3u);
  EXPECT_EQ(total.force_evaluations, 90u);
  EXPECT_EQ(total.smallest_step, 1e-4);
  EXPECT_EQ(total.largest_step, 2e-2);
  EXPECT_EQ(total.last_step, 1e-3) << "the current integrator's last step";
  EXPECT_EQ(total.cg_iterations, 47u);
  EXPECT_EQ(total.cg_max_iterations_in_a_step, 9u);
  EXPECT_EQ(total.cg_unconverged_solves, 1u);
  // A run that never switched: the empty statistics change nothing.
  const IntegratorStats alone = combine(IntegratorStats{}, later);
  IntegratorStats::for_each_field(alone, [&](std::string_view name, const auto& field, Tally) {
    IntegratorStats::for_each_field(later, [&](std::string_view other, const auto& value, Tally) {
      if constexpr (std::is_same_v<decltype(field), decltype(value)>) {
        if (name == other) {
          EXPECT_EQ(field, value) << name;
        }
      }
    });
  });
}

// A StateArchive that keeps the values of a save and gives them back on a load.
class MemoryArchive final : public StateArchive {
 public:
  bool loading() const override { return loading_; }
  void load() {
    loading_ = true;
    next_ = 0;
  }
  void value(std::string_view name, double& x) override { scalar(name, x); }
  void value(std::string_view name, std::uint64_t& x) override { scalar(name, x); }
  void text(std::string_view, std::string&) override {}
  void array(std::string_view, std::span<double>) override {}
  void array(std::string_view, std::span<Vec3>) override {}
  void array(std::string_view, std::span<std::uint8_t>) override {}
  void array(std::string_view, std::span<std::uint32_t>) override {}
  void array(std::string_view, std::span<std::int32_t>) override {}
  void expect_values(std::uint64_t, std::size_t) override {}
  std::vector<std::string> names;

 private:
  template <typename T>
  void scalar(std::string_view name, T& x) {
    if (!loading_) {
      names.emplace_back(name);
      stored_.push_back(static_cast<double>(x));
      return;
    }
    EXPECT_EQ(names.at(next_), name);
    x = static_cast<T>(stored_.at(next_++));
  }
  bool loading_ = false;
  std::size_t next_ = 0;
  std::vector<double> stored_;
};

TEST(RecordFields, ACheckpointKeepsEveryStoredField) {
  ContactStatistics saved;
  std::uint64_t value = 1;
  ContactStatistics::for_each_field(saved, [&](std::string_view, auto& field) { field = value++; });
  MemoryArchive archive;
  transfer_fields(archive, "contacts", saved);
  EXPECT_EQ(archive.names.front(), "contacts.contacts");
  EXPECT_EQ(archive.names.size(), 9u);
  ContactStatistics restored;
  archive.load();
  transfer_fields(archive, "contacts", restored);
  ContactStatistics::for_each_field(restored, [&, i = std::uint64_t{1}](std::string_view name, auto& field) mutable {
    EXPECT_EQ(field, i++) << name;
  });

  EnergyBalance balance;
  double x = 0.5;
  EnergyBalance::for_each_field(balance, [&](std::string_view, auto&& field, auto...) {
    if constexpr (!is_computed_v<decltype(field)>) field = (x += 1.0);
  });
  MemoryArchive energies;
  transfer_fields(energies, "run.initial", balance);
  EXPECT_EQ(energies.names.size(), 13u) << "the 13 stored terms and works, not the two computed values";
  EnergyBalance back;
  energies.load();
  transfer_fields(energies, "run.initial", back);
  EXPECT_EQ(back.error(), balance.error());
  EXPECT_EQ(back.edit_work, balance.edit_work);
  EXPECT_EQ(back.initial_total, balance.initial_total);
}

}  // namespace
}  // namespace clothsim
