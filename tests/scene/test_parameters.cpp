// The parameter registry: well-formed entries, number formatting, ranges, and docs in sync.
#include "scene/parameters.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace clothsim {
namespace {

TEST(Parameters, KeysAreUniqueAndFindable) {
  std::set<std::string_view> seen;
  for (std::string_view key : all_scene_keys()) EXPECT_TRUE(seen.insert(key).second) << key;
  for (const ScalarParameter& parameter : scalar_parameters()) {
    EXPECT_EQ(find_scalar_parameter(parameter.key), &parameter);
    EXPECT_FALSE(parameter.description.empty()) << parameter.key;
    EXPECT_LT(parameter.range.min, parameter.range.max) << parameter.key;
  }
  for (const VectorParameter& parameter : vector_parameters()) {
    EXPECT_EQ(find_vector_parameter(parameter.key), &parameter);
  }
  EXPECT_EQ(find_scalar_parameter("lattice.colums"), nullptr);
  EXPECT_EQ(find_vector_parameter("lattice.rows"), nullptr);
}

TEST(Parameters, DefaultsAreAllowed) {
  const SceneSpec defaults;
  for (const ScalarParameter& parameter : scalar_parameters()) {
    EXPECT_TRUE(is_allowed(parameter.type, parameter.range, parameter.get(defaults))) << parameter.key;
  }
  for (const VectorParameter& parameter : vector_parameters()) {
    const Vec3 value = parameter.get(defaults);
    for (int axis = 0; axis < 3; ++axis) EXPECT_TRUE(parameter.component_range.contains(value[axis])) << parameter.key;
  }
}

TEST(Parameters, GetReturnsWhatSetStored) {
  for (const ScalarParameter& parameter : scalar_parameters()) {
    SceneSpec spec;
    const double value = parameter.type == ParameterType::real ? parameter.range.max / 2.0 : parameter.range.max;
    parameter.set(spec, value);
    EXPECT_EQ(parameter.get(spec), value) << parameter.key;
  }
}

TEST(Parameters, Ranges) {
  const ValueRange open_closed = left_open_range(0.0, 1.0);
  EXPECT_FALSE(open_closed.contains(0.0));
  EXPECT_TRUE(open_closed.contains(1e-300));
  EXPECT_TRUE(open_closed.contains(1.0));
  EXPECT_FALSE(open_closed.contains(std::nan("")));
  EXPECT_FALSE(closed_range(-1e6, 1e6).contains(std::numeric_limits<double>::infinity()));
  EXPECT_TRUE(is_allowed(ParameterType::integer, closed_range(1, 4096), 3.0));
  EXPECT_FALSE(is_allowed(ParameterType::integer, closed_range(1, 4096), 2.5));
  EXPECT_FALSE(is_allowed(ParameterType::integer, closed_range(1, 4096), 0.0));
}

TEST(Parameters, FormatsNumbersCompactly) {
  EXPECT_EQ(format_number(0.0), "0");
  EXPECT_EQ(format_number(-0.0), "0");
  EXPECT_EQ(format_number(4096.0), "4096");
  EXPECT_EQ(format_number(2.5), "2.5");
  EXPECT_EQ(format_number(-1.0), "-1");
  EXPECT_EQ(format_number(1e9), "1e9");
  EXPECT_EQ(format_number(1e-6), "1e-6");
  EXPECT_EQ(format_number(1e-14), "1e-14");
  EXPECT_EQ(format_number(0.1), "0.1");
  EXPECT_EQ(format_number(10000.0), "10000");
  EXPECT_EQ(format_number(kLargestExactInteger), "9007199254740992");
  EXPECT_EQ(describe_range(closed_range(1, 4096)), "[1, 4096]");
  EXPECT_EQ(describe_range(left_open_range(0, 1000)), "(0, 1000]");
  EXPECT_EQ(describe_allowed(ParameterType::integer, closed_range(1, 4096)), "an integer in [1, 4096]");
  EXPECT_EQ(describe_allowed(ParameterType::real, left_open_range(0, 1e6)), "a number in (0, 1e6]");
  EXPECT_EQ(describe_allowed(ParameterType::boolean, closed_range(0, 1)), "a boolean (true or false)");
}

TEST(Parameters, RightAnglesConvertExactly) {
  EXPECT_EQ(degrees_to_radians(90.0), std::numbers::pi / 2.0);
  EXPECT_EQ(degrees_to_radians(180.0), std::numbers::pi);
  EXPECT_EQ(radians_to_degrees(std::numbers::pi / 2.0), 90.0);
  EXPECT_EQ(radians_to_degrees(std::numbers::pi), 180.0);
  EXPECT_EQ(degrees_to_radians(0.0), 0.0);
}

// docs/scene-format.md has one table row per key; the row states the range and the default.
TEST(Parameters, DocumentationListsEveryKeyWithRangeAndDefault) {
  std::ifstream file(CLOTHSIM_SOURCE_DIR "/docs/scene-format.md");
  ASSERT_TRUE(file) << "docs/scene-format.md is missing";
  std::vector<std::string> rows;
  for (std::string line; std::getline(file, line);) {
    if (line.starts_with("|")) rows.push_back(line);
  }
  const auto row_of = [&](std::string_view key) -> std::string {
    const std::string cell = "| `" + std::string(key) + "` |";
    for (const std::string& row : rows) {
      if (row.starts_with(cell)) return row;
    }
    return "";
  };
  const SceneSpec defaults;
  for (std::string_view key : all_scene_keys()) {
    EXPECT_FALSE(row_of(key).empty()) << "no table row for `" << key << "` in docs/scene-format.md";
  }
  for (const ScalarParameter& parameter : scalar_parameters()) {
    const std::string row = row_of(parameter.key);
    if (row.empty()) continue;
    if (parameter.type != ParameterType::boolean) {
      EXPECT_NE(row.find(describe_range(parameter.range)), std::string::npos)
          << parameter.key << ": the row should state the range " << describe_range(parameter.range) << "\n"
          << row;
    }
    const double value = parameter.get(defaults);
    const std::string default_text = format_parameter_value(parameter.type, value);
    EXPECT_NE(row.find("| " + default_text + " |"), std::string::npos)
        << parameter.key << ": the row should state the default " << default_text << "\n"
        << row;
  }
  for (const VectorParameter& parameter : vector_parameters()) {
    const std::string row = row_of(parameter.key);
    EXPECT_NE(row.find(describe_range(parameter.component_range)), std::string::npos) << parameter.key << "\n" << row;
  }
  // The fields of a material object, as material.<field>.
  for (const MaterialParameter& parameter : material_parameters()) {
    const std::string key = "material." + std::string(parameter.key);
    const std::string row = row_of(key);
    EXPECT_FALSE(row.empty()) << "no table row for `" << key << "` in docs/scene-format.md";
    EXPECT_NE(row.find(describe_range(parameter.range)), std::string::npos) << key << "\n" << row;
  }
}

}  // namespace
}  // namespace clothsim
