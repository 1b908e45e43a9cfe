#include "run/energy_table.h"

#include <array>
#include <cinttypes>
#include <type_traits>

namespace clothsim {

EnergyRow EnergyRow::of(std::uint64_t frame, const Simulation& simulation) {
  EnergyRow row;
  row.frame = frame;
  row.time = simulation.state().time;
  row.balance = simulation.energy_balance();
  row.stats = simulation.integrator_stats();
  row.changes = simulation.model_changes();
  row.contacts = simulation.contact_statistics();
  return row;
}

std::string energy_table_header() {
  std::string header;
  const EnergyRow row;
  EnergyRow::for_each_field(row, [&header](std::string_view name, auto&&...) {
    if (!header.empty()) header += ',';
    header += name;
  });
  return header;
}

std::string energy_table_row(const EnergyRow& row) {
  std::string text;
  EnergyRow::for_each_field(row, [&text](std::string_view, auto&& field, auto...) {
    const auto& value = field_value(field);
    using Value = std::remove_cvref_t<decltype(value)>;
    std::array<char, 32> cell{};
    if constexpr (std::is_integral_v<Value>) {
      std::snprintf(cell.data(), cell.size(), "%" PRIu64, static_cast<std::uint64_t>(value));
    } else {
      std::snprintf(cell.data(), cell.size(), "%.17g", static_cast<double>(value));
    }
    if (!text.empty()) text += ',';
    text += cell.data();
  });
  return text;
}

}  // namespace clothsim
