// Checked scene fields (json_fields.h).
#include "scene/json_fields.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"

namespace clothsim::scene_json {

[[noreturn]] void fail(const std::string& source, const std::string& field, const std::string& reason) {
  throw InputError(source, field, reason);
}

std::string join_key(std::string_view prefix, std::string_view name) {
  return prefix.empty() ? std::string(name) : std::string(prefix) + "." + std::string(name);
}

namespace {

std::string_view last_component(std::string_view key) {
  const std::size_t dot = key.rfind('.');
  return dot == std::string_view::npos ? key : key.substr(dot + 1);
}

std::string shorten(std::string text) {
  constexpr std::size_t kMaxQuoted = 60;
  if (text.size() > kMaxQuoted) text = text.substr(0, kMaxQuoted - 3) + "...";
  return text;
}

}  // namespace

std::string quoted(std::string_view text) { return "\"" + shorten(std::string(text)) + "\""; }

bool contains_name(const std::vector<std::string>& names, std::string_view name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::string describe_json(const json& value) {
  switch (value.type()) {
    case json::value_t::number_integer:
    case json::value_t::number_unsigned: return value.dump();
    case json::value_t::number_float: return format_number(value.get<double>());
    case json::value_t::string: return "string " + shorten(value.dump());
    case json::value_t::boolean: return std::string("boolean ") + (value.get<bool>() ? "true" : "false");
    case json::value_t::null: return "null";
    case json::value_t::array: return "array " + shorten(value.dump());
    case json::value_t::object: return "object " + shorten(value.dump());
    default: return shorten(value.dump());
  }
}

std::string describe_choice(const json& value) {
  return value.is_string() ? shorten(value.dump()) : describe_json(value);
}

// ---------------------------------------------------------------------------------------------
// Unknown keys and suggestions.

namespace {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> previous(b.size() + 1);
  std::vector<std::size_t> current(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) previous[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    current[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitution = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitution});
    }
    std::swap(previous, current);
  }
  return previous[b.size()];
}

// The candidate nearest to `name`, if it is close enough to be a plausible typo: at most 2 edits,
// or a third of the name for long names.
std::optional<std::string> nearest(std::string_view name, const std::vector<std::string>& candidates) {
  std::optional<std::string> best;
  std::size_t best_distance = std::max<std::size_t>(2, name.size() / 3) + 1;
  for (const std::string& candidate : candidates) {
    const std::size_t distance = edit_distance(name, candidate);
    if (distance < best_distance) {
      best_distance = distance;
      best = candidate;
    }
  }
  return best;
}

}  // namespace

std::string unknown_field_reason(std::string_view name, std::string_view prefix,
                                 const std::vector<std::string>& allowed) {
  if (const std::optional<std::string> match = nearest(name, allowed)) {
    return "unknown field (did you mean '" + join_key(prefix, *match) + "'?)";
  }
  for (std::string_view key : all_scene_keys()) {
    if (last_component(key) == name) return "unknown field (did you mean '" + std::string(key) + "'?)";
  }
  const std::string list = join_names(allowed);
  return prefix.empty() ? "unknown field (known fields: " + list + ")"
                        : "unknown field (known fields in '" + std::string(prefix) + "': " + list + ")";
}

std::vector<std::string> child_names(std::string_view prefix) {
  std::vector<std::string> names;
  for (std::string_view key : all_scene_keys()) {
    if (!prefix.empty()) {
      if (key.size() <= prefix.size() + 1 || !key.starts_with(prefix) || key[prefix.size()] != '.') continue;
      key.remove_prefix(prefix.size() + 1);
    }
    const std::string name(key.substr(0, key.find('.')));
    if (!contains_name(names, name)) names.push_back(name);
  }
  return names;
}

bool is_group(std::string_view key) {
  return std::any_of(all_scene_keys().begin(), all_scene_keys().end(), [&](std::string_view known) {
    return known.size() > key.size() && known.starts_with(key) && known[key.size()] == '.';
  });
}

void check_keys(const json& object, const std::vector<std::string>& allowed, const std::string& prefix,
                const std::string& source) {
  for (const auto& member : object.items()) {
    if (!contains_name(allowed, member.key())) {
      fail(source, join_key(prefix, member.key()), unknown_field_reason(member.key(), prefix, allowed));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Values from JSON.

namespace {

// The value of a JSON number. Integers beyond 2^53 are returned as infinity so that range checks
// reject them instead of accepting a rounded neighbour.
double json_number(const json& value) {
  if (value.is_number_unsigned()) {
    const auto number = value.get<std::uint64_t>();
    return number > static_cast<std::uint64_t>(kLargestExactInteger) ? kInfinity : static_cast<double>(number);
  }
  if (value.is_number_integer()) {
    const auto number = value.get<std::int64_t>();
    const auto limit = static_cast<std::int64_t>(kLargestExactInteger);
    if (number > limit || number < -limit) return number > 0 ? kInfinity : -kInfinity;
    return static_cast<double>(number);
  }
  return value.get<double>();
}

}  // namespace

double read_value(const json& value, ParameterType type, const ValueRange& range, const std::string& source,
                  const std::string& field) {
  if (type == ParameterType::boolean) {
    if (!value.is_boolean()) fail(source, field, "must be a boolean (true or false), got " + describe_json(value));
    return value.get<bool>() ? 1.0 : 0.0;
  }
  // A limit's "never" is JSON null; a number must be finite (an integer beyond 2^53 is not).
  if (type == ParameterType::limit && value.is_null()) return kInfinity;
  if (!value.is_number()) fail(source, field, "must be a number, got " + describe_json(value));
  const double number = json_number(value);
  const bool allowed = type == ParameterType::limit ? range.contains(number) : is_allowed(type, range, number);
  if (!allowed) fail(source, field, "must be " + describe_allowed(type, range) + ", got " + describe_json(value));
  return number;
}

Vec3 read_vector(const json& value, const ValueRange& range, const std::string& source, const std::string& field) {
  if (!value.is_array() || value.size() != 3) {
    fail(source, field, "must be an array of 3 numbers [x, y, z], got " + describe_json(value));
  }
  std::array<double, 3> components{};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    components[axis] =
        read_value(value[axis], ParameterType::real, range, source, field + "[" + std::to_string(axis) + "]");
  }
  return {components[0], components[1], components[2]};
}

std::string read_string(const json& value, const std::string& source, const std::string& field) {
  if (!value.is_string()) fail(source, field, "must be a string, got " + describe_json(value));
  return value.get<std::string>();
}

// ---------------------------------------------------------------------------------------------
// Values from command-line text.

bool is_utf8(std::string_view text, std::size_t* bad_at) {
  std::size_t i = 0;
  while (i < text.size()) {
    const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
    const unsigned char lead = byte(i);
    std::size_t length = 0;
    unsigned char low = 0x80;   // the allowed range of the second byte, which rules out overlong
    unsigned char high = 0xBF;  // forms, surrogates and code points past U+10FFFF
    if (lead < 0x80) {
      length = 1;
    } else if (lead >= 0xC2 && lead <= 0xDF) {
      length = 2;
    } else if (lead >= 0xE0 && lead <= 0xEF) {
      length = 3;
      if (lead == 0xE0) low = 0xA0;
      if (lead == 0xED) high = 0x9F;
    } else if (lead >= 0xF0 && lead <= 0xF4) {
      length = 4;
      if (lead == 0xF0) low = 0x90;
      if (lead == 0xF4) high = 0x8F;
    }
    bool valid = length > 0 && i + length <= text.size();
    for (std::size_t k = 1; valid && k < length; ++k) {
      const unsigned char next = byte(i + k);
      valid = k == 1 ? next >= low && next <= high : next >= 0x80 && next <= 0xBF;
    }
    if (!valid) {
      if (bad_at != nullptr) *bad_at = i;
      return false;
    }
    i += length;
  }
  return true;
}

std::string read_text_string(std::string_view text, const std::string& source, const std::string& field) {
  std::size_t bad_at = 0;
  if (!is_utf8(text, &bad_at)) {
    fail(source, field, "must be UTF-8 text, got bytes that are not UTF-8 at byte " + std::to_string(bad_at));
  }
  return std::string(text);
}

std::string_view trim(std::string_view text) {
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front()))) text.remove_prefix(1);
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.remove_suffix(1);
  return text;
}

namespace {

// A number written in `text`, or nullopt. "nan" and "inf" parse (to non-finite values, which every
// range rejects); an overflowing "1e400" becomes infinity for the same reason.
std::optional<double> parse_number_text(std::string_view text) {
  text = trim(text);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty()) return std::nullopt;
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (end != text.data() + text.size()) return std::nullopt;
  if (error == std::errc::result_out_of_range) return text.front() == '-' ? -kInfinity : kInfinity;
  if (error != std::errc()) return std::nullopt;
  return value;
}

}  // namespace

double read_text_value(std::string_view text, ParameterType type, const ValueRange& range, const std::string& source,
                       const std::string& field) {
  if (type == ParameterType::boolean) {
    const std::string_view word = trim(text);
    if (word == "true") return 1.0;
    if (word == "false") return 0.0;
    fail(source, field, "must be a boolean (true or false), got " + quoted(text));
  }
  // A limit's "never" is the word none; "inf" and overflowing numbers stay errors, as everywhere.
  if (type == ParameterType::limit && trim(text) == "none") return kInfinity;
  const std::optional<double> number = parse_number_text(text);
  if (!number) fail(source, field, "must be a number, got " + quoted(text));
  if (type == ParameterType::limit ? !range.contains(*number) : !is_allowed(type, range, *number)) {
    fail(source, field, "must be " + describe_allowed(type, range) + ", got " + quoted(trim(text)));
  }
  return *number;
}

std::vector<std::string_view> split_list(std::string_view text) {
  text = trim(text);
  if (text.size() >= 2 && text.front() == '[' && text.back() == ']') text = text.substr(1, text.size() - 2);
  std::vector<std::string_view> items;
  std::size_t start = 0;
  const auto is_separator = [](char c) { return c == ',' || std::isspace(static_cast<unsigned char>(c)); };
  while (start < text.size()) {
    while (start < text.size() && is_separator(text[start])) ++start;
    std::size_t end = start;
    while (end < text.size() && !is_separator(text[end])) ++end;
    if (end > start) items.push_back(text.substr(start, end - start));
    start = end;
  }
  return items;
}

Vec3 read_text_vector(std::string_view text, const ValueRange& range, const std::string& source,
                      const std::string& field) {
  const std::vector<std::string_view> items = split_list(text);
  if (items.size() != 3) fail(source, field, "must be 3 numbers x,y,z, got " + quoted(text));
  std::array<double, 3> components{};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    components[axis] =
        read_text_value(items[axis], ParameterType::real, range, source, field + "[" + std::to_string(axis) + "]");
  }
  return {components[0], components[1], components[2]};
}

// ---------------------------------------------------------------------------------------------
// JSON text.

namespace {

// nlohmann keeps the last of two equal keys. "rows" written twice is almost surely an editing
// slip, so this parser callback reports it, with the dotted path of the object.
class DuplicateKeyCheck {
 public:
  explicit DuplicateKeyCheck(const std::string& source) : source_(source) {}

  bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start: {
        std::string path = start_element();
        containers_.push_back({std::move(path), event == json::parse_event_t::array_start, 0, {}, {}});
        break;
      }
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end: containers_.pop_back(); break;
      case json::parse_event_t::key: {
        Container& object = containers_.back();
        object.last_key = parsed.get<std::string>();
        if (!object.keys.insert(object.last_key).second) {
          fail(source_, join_key(object.path, object.last_key), "appears twice in the same object");
        }
        break;
      }
      case json::parse_event_t::value: start_element(); break;
    }
    return true;
  }

 private:
  struct Container {
    std::string path;
    bool is_array = false;
    std::size_t next_index = 0;
    std::set<std::string> keys;
    std::string last_key;
  };

  // Dotted path of the value that starts now, inside the innermost container.
  std::string start_element() {
    if (containers_.empty()) return "";
    Container& parent = containers_.back();
    if (!parent.is_array) return join_key(parent.path, parent.last_key);
    return parent.path + "[" + std::to_string(parent.next_index++) + "]";
  }

  std::string source_;
  std::vector<Container> containers_;
};

// "line 3, column 7" of the character at 1-based offset `byte` (nlohmann's parse_error::byte, the
// position of the last character read).
std::string line_and_column(std::string_view text, std::size_t byte) {
  const std::size_t offset = std::min(byte > 0 ? byte - 1 : 0, text.size());  // 0-based
  const std::string_view before = text.substr(0, offset);
  const auto line = 1 + static_cast<std::size_t>(std::count(before.begin(), before.end(), '\n'));
  const std::size_t line_start = before.rfind('\n');  // npos on the first line
  const std::size_t column = line_start == std::string_view::npos ? offset + 1 : offset - line_start;
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// nlohmann's message without its "[json.exception.parse_error.101] parse error at line 3, column 7: "
// prefix, which we replace with our own position.
std::string syntax_error_detail(const std::string& what) {
  const std::size_t error_at = what.find("parse error");
  const std::size_t colon = error_at == std::string::npos ? std::string::npos : what.find(": ", error_at);
  if (colon != std::string::npos) {
    std::string detail = what.substr(colon + 2);
    // "syntax error while parsing value - ..." follows our own "JSON syntax error: ".
    constexpr std::string_view kRepeated = "syntax error ";
    if (detail.starts_with(kRepeated)) detail.erase(0, kRepeated.size());
    return detail;
  }
  const std::size_t bracket = what.find("] ");
  return bracket == std::string::npos ? what : what.substr(bracket + 2);
}

}  // namespace

json parse_json(std::string_view text, const std::string& source) {
  try {
    return json::parse(text.begin(), text.end(), DuplicateKeyCheck(source), /*allow_exceptions=*/true,
                       /*ignore_comments=*/true);
  } catch (const json::parse_error& error) {
    fail(source, "", line_and_column(text, error.byte) + ": JSON syntax error: " + syntax_error_detail(error.what()));
  } catch (const json::exception& error) {
    fail(source, "", "JSON error: " + syntax_error_detail(error.what()));
  }
}

}  // namespace clothsim::scene_json
