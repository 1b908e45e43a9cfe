// Checked scene fields: the one place that turns JSON values, and the text of `--set key=value`,
// into fields checked against their type and range, with messages that name the file, the dotted
// field ("anchors[2].path.frequency") and what is allowed.
//
// Internal to src/scene, not part of scene.h. The reader of the whole document (scene.cpp), the
// anchors and cuts (anchors_json.cpp) and the material (material_json.cpp) all read through these
// functions, so that a value meets the same check and the same message wherever it is written.
// Every failure is an InputError thrown by fail(); check_keys() rejects unknown keys and suggests
// the nearest known one.
#pragma once

#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "core/vec3.h"
#include "scene/parameters.h"

namespace clothsim::scene_json {

using json = nlohmann::json;

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Throws InputError(source, field, reason).
[[noreturn]] void fail(const std::string& source, const std::string& field, const std::string& reason);

// "prefix.name", or "name" when the prefix is empty.
std::string join_key(std::string_view prefix, std::string_view name);
// `text` in double quotes, shortened to 60 characters.
std::string quoted(std::string_view text);

// "a, b, c".
template <typename Names>
std::string join_names(const Names& names) {
  std::string text;
  for (const auto& name : names) text += (text.empty() ? "" : ", ") + std::string(name);
  return text;
}

bool contains_name(const std::vector<std::string>& names, std::string_view name);

// How a JSON value is quoted after "got": `0`, `2.5`, `string "sixty"`, `boolean true`.
std::string describe_json(const json& value);

// For values that must be one of a few names: a string is quoted as is ("euler"), anything else
// with its type.
std::string describe_choice(const json& value);

// ---------------------------------------------------------------------------------------------
// Unknown keys and suggestions.

// "unknown field (did you mean 'lattice.cols'?)". `allowed` are the leaf names valid at this level
// and `prefix` their parent key. A name that exists elsewhere in the scene ("fps" at the top
// level) gets the full key of that place as its suggestion.
std::string unknown_field_reason(std::string_view name, std::string_view prefix,
                                 const std::vector<std::string>& allowed);

// Leaf names one level below `prefix` among all scene keys; "" is the top level.
std::vector<std::string> child_names(std::string_view prefix);

// A group of fields ("lattice", "springs.adjacent"): some known key lies below it.
bool is_group(std::string_view key);

// Throws for the first member of `object` not in `allowed`.
void check_keys(const json& object, const std::vector<std::string>& allowed, const std::string& prefix,
                const std::string& source);

// ---------------------------------------------------------------------------------------------
// Values from JSON.

double read_value(const json& value, ParameterType type, const ValueRange& range, const std::string& source,
                  const std::string& field);
Vec3 read_vector(const json& value, const ValueRange& range, const std::string& source, const std::string& field);
std::string read_string(const json& value, const std::string& source, const std::string& field);

// ---------------------------------------------------------------------------------------------
// Values from command-line text.

std::string_view trim(std::string_view text);
double read_text_value(std::string_view text, ParameterType type, const ValueRange& range, const std::string& source,
                       const std::string& field);
// Splits "a,b, c" or "a b c" (brackets around the list allowed) into its items.
std::vector<std::string_view> split_list(std::string_view text);
Vec3 read_text_vector(std::string_view text, const ValueRange& range, const std::string& source,
                      const std::string& field);
// Free text (a name, a description) as given, which must be UTF-8 as in a scene file: it is
// written into scene.json and summary.json, and JSON holds nothing else.
std::string read_text_string(std::string_view text, const std::string& source, const std::string& field);
// Whether `text` is well-formed UTF-8 (no overlong forms, surrogates or code points past
// U+10FFFF), what a JSON text must be; the byte offset of the first bad sequence in `bad_at`.
bool is_utf8(std::string_view text, std::size_t* bad_at = nullptr);

// ---------------------------------------------------------------------------------------------
// JSON text.

// The JSON value of `text`, comments allowed. A syntax error (with its line and column) or a key
// written twice in one object (with its dotted path) is an InputError.
json parse_json(std::string_view text, const std::string& source);

}  // namespace clothsim::scene_json
