// The scene key `cuts`: notches cut before the run, parsed, validated, round-tripped and applied
// by build_model() to exactly the connectors the segment crosses.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_model.h"
#include "test_checks.h"

namespace clothsim {
namespace {

using checks::contains;
using checks::thrown_message;

constexpr const char* kNotched = R"({"lattice": {"rows": 6, "cols": 5},
  "cuts": [{"from": [2.5, -1], "to": [2.5, 1.5]}, {"from": [-1, 3.5], "to": [0.5, 3.5]}]})";

TEST(SceneCuts, AreParsedAndApplied) {
  const SceneSpec spec = parse_scene(kNotched, "notched.json");
  ASSERT_EQ(spec.cuts.size(), 2u);
  EXPECT_EQ(spec.cuts[0].from, (std::array<double, 2>{2.5, -1.0}));
  const ClothModel model = build_model(spec);
  // The first cut crosses the south connectors of (2, 0) and (2, 1); the second the east
  // connector of (0, 3).
  std::vector<std::array<std::uint32_t, 2>> broken;
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    if (model.connector_live[e] == 0) {
      broken.push_back(model.connector_particles[e]);
      EXPECT_EQ(model.connector_break_time[e], 0.0);
    }
  }
  const std::vector<std::array<std::uint32_t, 2>> expected = {{3, 4}, {10, 15}, {11, 16}};
  EXPECT_EQ(broken, expected);
  EXPECT_EQ(model.broken_connector_count, 3u);
}

TEST(SceneCuts, RoundTripAndSetFromTheCommandLine) {
  const SceneSpec spec = parse_scene(kNotched, "notched.json");
  EXPECT_EQ(parse_scene(scene_to_json(spec).dump(), "round trip").cuts, spec.cuts);
  SceneSpec edited;
  set_scene_field(edited, "cuts", R"([{"from": [1, 1], "to": [2, 2]}])", "--set cuts");
  ASSERT_EQ(edited.cuts.size(), 1u);
  EXPECT_EQ(edited.cuts[0].to, (std::array<double, 2>{2.0, 2.0}));
}

TEST(SceneCuts, BadCutsNameTheFileAndTheField) {
  const auto error = [](const std::string& cuts) {
    return thrown_message([&] { parse_scene(R"({"cuts": )" + cuts + "}", "bad.json"); });
  };
  EXPECT_TRUE(contains(error(R"("notch")"), "bad.json")) << error(R"("notch")");
  EXPECT_TRUE(contains(error(R"([{"from": [1, 2]}])"), "cuts[0].to")) << error(R"([{"from": [1, 2]}])");
  EXPECT_TRUE(contains(error(R"([{"from": [1], "to": [1, 2]}])"), "cuts[0].from"));
  EXPECT_TRUE(contains(error(R"([{"from": [1, 2], "to": [1, 2e7]}])"), "cuts[0].to[1]"));
  EXPECT_TRUE(contains(error(R"([{"from": [1, 2], "to": [1, 2], "depth": 3}])"), "depth"));
}

}  // namespace
}  // namespace clothsim
