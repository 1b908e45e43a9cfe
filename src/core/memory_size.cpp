#include "core/memory_size.h"

#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace clothsim {
namespace {

struct Unit {
  std::string_view name;  // lower case
  double bytes;
};

constexpr double kKibi = 1024.0;
constexpr std::array<Unit, 15> kUnits = {{
    {"", 1.0},
    {"b", 1.0},
    {"k", kKibi},
    {"kib", kKibi},
    {"kb", 1e3},
    {"m", kKibi* kKibi},
    {"mib", kKibi* kKibi},
    {"mb", 1e6},
    {"g", kKibi* kKibi* kKibi},
    {"gib", kKibi* kKibi* kKibi},
    {"gb", 1e9},
    {"t", kKibi* kKibi* kKibi* kKibi},
    {"tib", kKibi* kKibi* kKibi* kKibi},
    {"tb", 1e12},
    {"bytes", 1.0},
}};

}  // namespace

std::string_view memory_size_forms() {
  return "a size such as 512M, 8G, 2GiB, 1.5GB or a number of bytes (K, M, G, T and KiB, MiB, GiB, TiB are "
         "powers of 1024; KB, MB, GB, TB powers of 1000)";
}

std::optional<std::uint64_t> parse_memory_size(std::string_view text) {
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front())) != 0) text.remove_prefix(1);
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back())) != 0) text.remove_suffix(1);
  // The number: digits with at most one point, at least one digit.
  std::size_t end = 0;
  int digits = 0;
  int points = 0;
  while (end < text.size() && (std::isdigit(static_cast<unsigned char>(text[end])) != 0 || text[end] == '.')) {
    (text[end] == '.' ? points : digits) += 1;
    ++end;
  }
  if (digits == 0 || points > 1) return std::nullopt;
  const std::string number(text.substr(0, end));
  std::string_view unit_text = text.substr(end);
  while (!unit_text.empty() && unit_text.front() == ' ') unit_text.remove_prefix(1);
  std::string unit;
  for (char c : unit_text) unit += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const Unit& candidate : kUnits) {
    if (candidate.name != unit) continue;
    const double bytes = std::strtod(number.c_str(), nullptr) * candidate.bytes;
    // 2^63: beyond any machine, and past what a signed 64-bit count holds.
    if (!(bytes >= 1.0) || !(bytes < 9.2233720368547758e18)) return std::nullopt;
    return static_cast<std::uint64_t>(std::llround(bytes));
  }
  return std::nullopt;
}

std::string format_memory_size(std::uint64_t bytes) {
  if (bytes < 1024) return std::to_string(bytes) + (bytes == 1 ? " byte" : " bytes");
  constexpr std::array<std::string_view, 6> kNames = {"KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  double value = static_cast<double>(bytes) / kKibi;
  std::size_t unit = 0;
  // 999.5 and up would print as "1.00e+03": move to the next unit first.
  while (value >= 999.5 && unit + 1 < kNames.size()) {
    value /= kKibi;
    ++unit;
  }
  char buffer[32];
  std::snprintf(buffer, sizeof buffer,
                value >= 99.95   ? "%.0f %.*s"
                : value >= 9.995 ? "%.1f %.*s"
                                 : "%.2f %.*s",
                value, static_cast<int>(kNames[unit].size()), kNames[unit].data());
  return buffer;
}

}  // namespace clothsim
