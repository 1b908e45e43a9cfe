// Records and their one field list.
//
// A record (EnergyReport, EnergyBalance, IntegratorStats, ContactStatistics, ...) lists its fields
// once, beside its definition, in a static member template
//
//   template <typename Self, typename Visit>
//   static void for_each_field(Self& self, Visit&& visit);
//
// that calls visit(name, field) for every field in order: `field` is the member itself (const when
// `self` is), or a Computed value for what the record derives from its members (an energy's
// total, the balance error), which is reported but never stored. A field may carry a third
// argument, how it adds up over the integrators of a run (Tally); visitors that do not need it
// take `auto...` after the field, and the field as `auto&&` (a Computed value is a temporary). Every writer of a record
// walks this list: the checkpoints (transfer_fields below), summary.json, the sweep's index and the Python module, so
// adding a field is one line beside the record. energy.csv is a record of its own (run/energy_table.h), one row per
// frame, whose columns take their values from these.
//
// After MuJoCo's X-macro field lists (mjxmacro.h), written as a plain function template: no
// macros, and the compiler checks every visitor against every field's type.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <type_traits>

#include "core/state_archive.h"

namespace clothsim {

// A value a record derives from its fields: reported (summary.json, the Python module), never
// saved or restored.
template <typename T>
struct Computed {
  T value;
};

template <typename T>
struct is_computed : std::false_type {};
template <typename T>
struct is_computed<Computed<T>> : std::true_type {};
// True for Computed<T>, with or without const and reference.
template <typename T>
inline constexpr bool is_computed_v = is_computed<std::remove_cvref_t<T>>::value;

// The value of a field as visited: the member, or a Computed's value.
template <typename T>
const T& field_value(const T& field) {
  return field;
}
template <typename T>
const T& field_value(const Computed<T>& field) {
  return field.value;
}

// How a counter adds up when a run's statistics are summed over its integrators
// (Simulation::set_integrator replaces one mid-run): summed, the least, the greatest, or the
// latest one's.
enum class Tally { sum, least, greatest, latest };

// Visits the stored fields of two records of one type side by side, as
// visit(name, a's field, b's field, the field's tags...).
template <typename Record, typename Visit>
void for_each_field_pair(Record& a, const Record& b, Visit&& visit) {
  // b's fields in order, then each of a's with the one at its position: the same list, so the
  // same types (the void pointers are cast back to the type they were taken from).
  constexpr std::size_t kMaxFields = 64;
  std::array<const void*, kMaxFields> others{};
  std::size_t count = 0;
  Record::for_each_field(b, [&](std::string_view, auto&& field, auto...) {
    if constexpr (!is_computed_v<decltype(field)>) others.at(count++) = &field;
  });
  std::size_t index = 0;
  Record::for_each_field(a, [&](std::string_view name, auto&& field, auto... tags) {
    if constexpr (!is_computed_v<decltype(field)>) {
      using Field = std::remove_reference_t<decltype(field)>;
      visit(name, field, *static_cast<const Field*>(others.at(index++)), tags...);
    }
  });
}

// Saves or restores every stored field of `record` (Computed values are skipped) as
// "<prefix>.<name>", in the record's order.
template <typename Record>
void transfer_fields(StateArchive& archive, std::string_view prefix, Record& record) {
  Record::for_each_field(record, [&](std::string_view name, auto&& field, auto...) {
    if constexpr (!is_computed_v<decltype(field)>) {
      std::string key(prefix);
      key += '.';
      key += name;
      archive.value(key, field);
    }
  });
}

}  // namespace clothsim
