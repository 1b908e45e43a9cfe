// The paper's argument vector; see paper_args.h.
#include "scene/paper_args.h"

#include <string>
#include <vector>

#include "scene/json_fields.h"
#include "scene/parameters.h"

namespace clothsim {
namespace scene_json {
namespace {

struct PaperArgument {
  std::string_view key;   // registry key the argument sets
  std::string_view name;  // as the paper lists it
};

constexpr std::array<PaperArgument, 10> kPaperArguments = {{
    {"lattice.rows", "rows"},
    {"lattice.cols", "cols"},
    {"lattice.particle_mass", "mass"},
    {"springs.adjacent.stiffness", "k adjacent"},
    {"springs.adjacent.damping", "c adjacent"},
    {"springs.opposite.stiffness", "k opposite"},
    {"springs.opposite.damping", "c opposite"},
    {"springs.connector.stiffness", "k connector"},
    {"springs.connector.damping", "c connector"},
    {"lattice.spacing", "connector length"},
}};

std::string paper_argument_field(std::size_t i) {
  return "paper_args[" + std::to_string(i) + "] (" + std::string(kPaperArguments[i].name) + ")";
}

std::string paper_argument_count_reason(std::size_t count) {
  std::vector<std::string_view> names;
  for (const PaperArgument& argument : kPaperArguments) names.push_back(argument.name);
  return "must be exactly 10 numbers (" + join_names(names) + "), got " + std::to_string(count);
}

}  // namespace

void apply_paper_arguments(SceneSpec& spec, const std::array<double, 10>& values) {
  for (std::size_t i = 0; i < kPaperArguments.size(); ++i) {
    find_scalar_parameter(kPaperArguments[i].key)->set(spec, values[i]);
  }
  parse_anchor_preset("center", spec.lattice, spec.anchors);
}

std::array<double, 10> read_paper_arguments(const json& value, const std::string& source) {
  if (!value.is_array()) fail(source, "paper_args", "must be an array of 10 numbers, got " + describe_json(value));
  if (value.size() != kPaperArguments.size()) fail(source, "paper_args", paper_argument_count_reason(value.size()));
  std::array<double, 10> values{};
  for (std::size_t i = 0; i < values.size(); ++i) {
    const ScalarParameter& parameter = *find_scalar_parameter(kPaperArguments[i].key);
    values[i] = read_value(value[i], parameter.type, parameter.range, source, paper_argument_field(i));
  }
  return values;
}

std::array<double, 10> read_text_paper_arguments(std::string_view text, const std::string& source) {
  const std::vector<std::string_view> items = split_list(text);
  if (items.size() != kPaperArguments.size()) fail(source, "paper_args", paper_argument_count_reason(items.size()));
  std::array<double, 10> values{};
  for (std::size_t i = 0; i < values.size(); ++i) {
    const ScalarParameter& parameter = *find_scalar_parameter(kPaperArguments[i].key);
    values[i] = read_text_value(items[i], parameter.type, parameter.range, source, paper_argument_field(i));
  }
  return values;
}

}  // namespace scene_json
}  // namespace clothsim
