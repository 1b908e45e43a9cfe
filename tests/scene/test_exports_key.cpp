// Tests of the scene key output.export (scene.cpp): read from files and from --set text, written
// back by scene_to_json, and refused with a message naming the field and the formats there are.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/error.h"
#include "scene/scene.h"

namespace clothsim {
namespace {

using Exports = std::vector<ExportFormat>;

// The message of the InputError that `action` throws, or "" (a failure) if it throws none.
template <typename Action>
std::string error_of(Action action) {
  try {
    action();
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

TEST(ExportsKey, DefaultsToNone) { EXPECT_TRUE(SceneSpec{}.output.exports.empty()); }

TEST(ExportsKey, ReadsAListInOrderDroppingRepeats) {
  const SceneSpec spec = parse_scene(R"({"output": {"export": ["obj-sequence", "pc2", "obj-sequence"]}})", "s.json");
  EXPECT_EQ(spec.output.exports, (Exports{ExportFormat::obj_sequence, ExportFormat::pc2}));
  const nlohmann::json written = scene_to_json(spec);
  EXPECT_EQ(written["output"]["export"], nlohmann::json::array({"obj-sequence", "pc2"}));
  EXPECT_EQ(parse_scene(written.dump(), "again").output.exports, spec.output.exports);
}

TEST(ExportsKey, SetFromCommaSeparatedText) {
  SceneSpec spec;
  set_scene_field(spec, "output.export", "pc2,obj-sequence,gltf", "--export");
  EXPECT_EQ(spec.output.exports, (Exports{ExportFormat::pc2, ExportFormat::obj_sequence, ExportFormat::gltf}));
  set_scene_field(spec, "output.export", "none", "--export");
  EXPECT_TRUE(spec.output.exports.empty());
  set_scene_field(spec, "output.export", "pc2", "--export");
  EXPECT_EQ(spec.output.exports, (Exports{ExportFormat::pc2}));
}

TEST(ExportsKey, UnknownNamesNameTheFieldAndTheFormats) {
  const std::string text = error_of([] {
    SceneSpec spec;
    set_scene_field(spec, "output.export", "pc2,fbx", "--export");
  });
  for (const char* piece : {"--export", "output.export", "pc2, obj-sequence, gltf", "\"fbx\""}) {
    EXPECT_NE(text.find(piece), std::string::npos) << piece << " in: " << text;
  }
  const std::string file = error_of([] { parse_scene(R"({"output": {"export": ["pc2", 3]}})", "s.json"); });
  EXPECT_NE(file.find("output.export"), std::string::npos) << file;
  const std::string not_list = error_of([] { parse_scene(R"({"output": {"export": "pc2"}})", "s.json"); });
  EXPECT_NE(not_list.find("must be a list"), std::string::npos) << not_list;
}

}  // namespace
}  // namespace clothsim
