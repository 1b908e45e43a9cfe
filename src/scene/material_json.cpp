// The "material" object of scene files (material_json.h).
#include "scene/material_json.h"

#include <string>
#include <vector>

#include "model/spring_limits.h"
#include "scene/parameters.h"

namespace clothsim::scene_json {

namespace {

std::string material_choices() { return material_preset_names(); }

}  // namespace

void check_material(const MaterialDef& material, const std::string& source, const std::string& field) {
  if (!(material.areal_density > 0.0)) {
    fail(source, field + ".areal_density", "is required: a material object needs its mass per area (kg/m^2)");
  }
  if (yields_after_breaking(material.yield_strain, material.break_strain)) {
    fail(source, field + ".yield_strain",
         "must be <= " + field + ".break_strain (" + format_number(material.break_strain) + "), got " +
             format_number(material.yield_strain) + ": the sheet would tear before it stretches for good");
  }
}

MaterialDef read_material(const json& value, const std::string& source, const std::string& field) {
  const std::string allowed = "must be one of " + material_choices() + " or an object of material fields, got ";
  if (value.is_string()) {
    const MaterialDef* preset = find_material_preset(value.get<std::string>());
    if (preset == nullptr) fail(source, field, allowed + describe_choice(value));
    return *preset;
  }
  if (!value.is_object()) fail(source, field, allowed + describe_json(value));
  std::vector<std::string> keys = {"name"};
  for (const MaterialParameter& parameter : material_parameters()) keys.emplace_back(parameter.key);
  check_keys(value, keys, field, source);
  MaterialDef material;
  material.name = "custom";
  for (const auto& member : value.items()) {
    const std::string member_field = join_key(field, member.key());
    if (member.key() == "name") {
      material.name = read_string(member.value(), source, member_field);
      continue;
    }
    const MaterialParameter& parameter = *find_material_parameter(member.key());
    parameter.set(material, read_value(member.value(), parameter.type, parameter.range, source, member_field));
  }
  check_material(material, source, field);
  return material;
}

json material_to_json(const MaterialDef& material) {
  const MaterialDef* preset = find_material_preset(material.name);
  if (preset != nullptr && *preset == material) return material.name;
  json out = {{"name", material.name}};
  for (const MaterialParameter& parameter : material_parameters()) {
    const double value = parameter.get(material);
    out[std::string(parameter.key)] = value == kInfinity ? json(nullptr) : json(value);
  }
  return out;
}

}  // namespace clothsim::scene_json
