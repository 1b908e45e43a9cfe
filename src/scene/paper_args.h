// The paper's argument vector (cloth-simulation-paper.md): ten numbers, rows, cols, mass, the
// (k, c) of the adjacent, opposite and connector springs, and the connector length, read from a
// scene's "paper_args" member or the --paper-args flag and applied field by field through the
// parameter registry, each number checked against its field's range.
#pragma once

#include <array>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "scene/scene.h"

namespace clothsim::scene_json {

// The ten numbers of a JSON array, each checked; throws InputError naming `source` and the
// argument ("paper_args[2] (mass)").
std::array<double, 10> read_paper_arguments(const nlohmann::json& value, const std::string& source);
// The same from comma-separated text (--paper-args).
std::array<double, 10> read_text_paper_arguments(std::string_view text, const std::string& source);
// Sets the ten fields (values already checked) and anchors the centre particle, as in every run
// of the paper.
void apply_paper_arguments(SceneSpec& spec, const std::array<double, 10>& values);

}  // namespace clothsim::scene_json
