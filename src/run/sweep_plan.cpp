#include "run/sweep_plan.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <fstream>
#include <sstream>
#include <system_error>

#include "core/error.h"
#include "run/run_checkpoints.h"
#include "run/run_folders.h"
#include "run/run_writer.h"
#include "scene/json_fields.h"
#include "scene/validate_scene.h"
#include "sim/statistics.h"

namespace clothsim {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using scene_json::trim;

constexpr std::string_view kRecordFile = "sweep.json";
constexpr std::string_view kIndexFile = "index.csv";

[[noreturn]] void bad_param(const std::string& field, const std::string& reason, std::string_view source = "--param") {
  throw InputError(std::string(source), field, reason);
}

// Splits at commas outside [] and {}.
std::vector<std::string> split_values(std::string_view text, const std::string& key) {
  std::vector<std::string> values;
  int depth = 0;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= text.size(); ++i) {
    const char c = i < text.size() ? text[i] : ',';
    if (c == '[' || c == '{') ++depth;
    if (c == ']' || c == '}') {
      if (--depth < 0) bad_param(key, "has a '" + std::string(1, c) + "' without its opening bracket");
    }
    if (c != ',' || depth > 0) continue;
    const std::string_view value = trim(text.substr(start, i - start));
    if (value.empty()) bad_param(key, "has an empty value; expected KEY=V1,V2,... (got \"" + std::string(text) + "\")");
    values.emplace_back(value);
    start = i + 1;
  }
  if (depth != 0) bad_param(key, "has a bracket that is not closed");
  return values;
}

std::size_t read_count(std::string_view text, std::string_view what, const std::string& whole) {
  std::size_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || end != text.data() + text.size() || text.empty()) {
    throw InputError("--shard", "",
                     "expects K/N with whole numbers 1 <= K <= N, got \"" + whole + "\" (" + std::string(what) +
                         " is not a whole number)");
  }
  return value;
}

json read_json(const fs::path& path) {
  std::ifstream in(path);
  if (!in) return json();
  return json::parse(in, nullptr, /*allow_exceptions=*/false);
}

// A CSV cell: quoted when it holds a comma, quote or line break.
std::string csv_cell(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

// A number as summary.json holds it, in the shortest text that reads back to the same double, or
// "" when absent.
std::string number_cell(const json& value) {
  if (!value.is_number()) return {};
  if (value.is_number_integer()) return std::to_string(value.get<long long>());
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value.get<double>());
  return std::string(text, result.ptr);
}

const json& at_path(const json& root, std::initializer_list<std::string_view> path) {
  static const json kMissing;
  const json* node = &root;
  for (std::string_view key : path) {
    if (!node->is_object()) return kMissing;
    const auto found = node->find(std::string(key));
    if (found == node->end()) return kMissing;
    node = &*found;
  }
  return *node;
}

// The energy terms and works of summary.json's "energy", by EnergyBalance's one field list.
std::vector<std::string_view> final_energy_terms() {
  std::vector<std::string_view> terms;
  const EnergyBalance balance;
  EnergyBalance::for_each_field(balance, [&terms](std::string_view name, auto&&...) { terms.push_back(name); });
  return terms;
}

}  // namespace

SweepParameter parse_sweep_parameter(std::string_view text) {
  const std::size_t equals = text.find('=');
  if (equals == std::string_view::npos || equals == 0) {
    bad_param("", "expects KEY=V1,V2,... (list the keys with 'clothsim params'), got \"" + std::string(text) + "\"");
  }
  SweepParameter parameter{std::string(trim(text.substr(0, equals))), {}};
  parameter.values = split_values(text.substr(equals + 1), parameter.key);
  for (std::size_t i = 0; i < parameter.values.size(); ++i) {
    if (std::find(parameter.values.begin(), parameter.values.begin() + i, parameter.values[i]) !=
        parameter.values.begin() + i) {
      bad_param(parameter.key, "lists the value " + parameter.values[i] + " twice");
    }
  }
  return parameter;
}

Shard parse_shard(std::string_view text) {
  const std::string whole(text);
  const std::size_t slash = text.find('/');
  if (slash == std::string_view::npos) {
    throw InputError("--shard", "", "expects K/N (run the K-th of N shares, 1 <= K <= N), got \"" + whole + "\"");
  }
  Shard shard{read_count(text.substr(0, slash), "K", whole), read_count(text.substr(slash + 1), "N", whole)};
  if (shard.count < 1 || shard.count > kMaxSweepRuns) {
    throw InputError("--shard", "",
                     "N must be in [1, " + std::to_string(kMaxSweepRuns) + "], got " + std::to_string(shard.count));
  }
  if (shard.index < 1 || shard.index > shard.count) {
    throw InputError("--shard", "",
                     "K must be in [1, " + std::to_string(shard.count) + "] (shares count from 1), got " +
                         std::to_string(shard.index));
  }
  return shard;
}

std::vector<SweepRun> plan_sweep(const std::vector<SweepParameter>& parameters, std::string_view source) {
  std::size_t total = 1;
  for (std::size_t p = 0; p < parameters.size(); ++p) {
    for (std::size_t q = 0; q < p; ++q) {
      if (parameters[q].key == parameters[p].key)
        bad_param(parameters[p].key, "is swept by two " + std::string(source) + " options", source);
    }
    if (parameters[p].values.empty()) bad_param(parameters[p].key, "has no values", source);
    total *= parameters[p].values.size();
    if (total > kMaxSweepRuns) {
      bad_param(parameters[p].key, "the grid has more than " + std::to_string(kMaxSweepRuns) + " runs", source);
    }
  }
  const std::size_t width = std::max<std::size_t>(4, std::to_string(total - 1).size());
  std::vector<SweepRun> runs(total);
  for (std::size_t i = 0; i < total; ++i) {
    SweepRun& run = runs[i];
    run.index = i;
    const std::string number = std::to_string(i);
    run.folder = "run-" + std::string(width - number.size(), '0') + number;
    // Mixed radix, the last --param the fastest digit.
    std::size_t rest = i;
    run.assignments.resize(parameters.size());
    for (std::size_t p = parameters.size(); p-- > 0;) {
      const std::size_t count = parameters[p].values.size();
      run.assignments[p] = {parameters[p].key, parameters[p].values[rest % count]};
      rest /= count;
    }
  }
  return runs;
}

void check_sweep_scenes(const SceneSpec& base, const std::vector<SweepRun>& runs, std::string_view source) {
  const std::string name(source);
  for (const SweepRun& run : runs) {
    SceneSpec spec = base;
    std::string where = name + " (" + run.folder;
    for (const auto& [key, value] : run.assignments) {
      set_scene_field(spec, key, value, name);
      where += ", " + key + "=" + value;
    }
    validate_scene(spec, where + ")");
  }
}

std::string_view to_string(SweepRunState state) {
  switch (state) {
    case SweepRunState::pending: return "pending";
    case SweepRunState::running: return "running";
    case SweepRunState::interrupted: return "interrupted";
    case SweepRunState::completed: return "completed";
    case SweepRunState::failed: return "failed";
    case SweepRunState::error: return "error";
  }
  return "unknown";
}

fs::path sweep_log_path(const fs::path& out, const SweepRun& run) { return out / "logs" / (run.folder + ".log"); }

SweepRunStatus read_run_status(const fs::path& out, const SweepRun& run) {
  SweepRunStatus status;
  const fs::path folder = out / run.folder;
  status.summary = read_json(folder / RunWriter::kSummaryFile);
  const json& state = at_path(status.summary, {"status"});
  if (state.is_string()) {
    const std::string text = state.get<std::string>();
    if (text == "completed" || text == "at_rest") {
      status.state = SweepRunState::completed;
      return status;
    }
    status.state = text == "failed" ? SweepRunState::failed : SweepRunState::interrupted;
    if (status.state == SweepRunState::interrupted && !list_run_checkpoints(folder).empty())
      status.resume_from = folder;
  }
  // A partial folder beside it: a run still going, or one that died (resumable from a checkpoint).
  for (const LeftoverRun& partial : find_partial_runs(folder)) {
    if (partial.alive) {
      status.state = SweepRunState::running;
      return status;
    }
    if (status.state == SweepRunState::pending) status.state = SweepRunState::interrupted;
    if (status.resume_from.empty() && partial.has_checkpoint) status.resume_from = partial.folder;
  }
  std::error_code error;
  if (status.state == SweepRunState::pending && fs::exists(sweep_log_path(out, run), error))
    status.state = SweepRunState::error;
  return status;
}

json sweep_record(const std::vector<std::string>& scene_arguments, const std::vector<SweepParameter>& parameters,
                  std::size_t runs) {
  json grid = json::array();
  for (const SweepParameter& parameter : parameters)
    grid.push_back({{"key", parameter.key}, {"values", parameter.values}});
  return {{"run_arguments", scene_arguments}, {"parameters", grid}, {"runs", runs}};
}

void claim_sweep_folder(const fs::path& out, const json& record, std::string_view source) {
  std::error_code error;
  const fs::path record_path = out / kRecordFile;
  if (fs::exists(record_path, error)) {
    const json existing = read_json(record_path);
    if (existing == record) return;
    throw InputError(std::string(source), "",
                     out.string() + " holds another sweep (its " + std::string(kRecordFile) +
                         " has other parameters or run arguments): give another folder, or the same arguments as "
                         "before to continue that sweep");
  }
  if (fs::exists(out, error) && !fs::is_empty(out, error)) {
    throw InputError(std::string(source), "",
                     out.string() + " exists and is not a sweep's folder (no " + std::string(kRecordFile) +
                         "): give a new or empty folder");
  }
  fs::create_directories(out / "logs", error);
  if (error) throw OutputError(out.string() + ": cannot create the sweep's folder: " + error.message());
  write_text_atomically(record_path, record.dump(2) + "\n");
}

void write_sweep_index(const fs::path& out, const std::vector<SweepParameter>& parameters,
                       const std::vector<SweepRun>& runs) {
  std::ostringstream csv;
  csv << "run,folder";
  for (const SweepParameter& parameter : parameters) csv << ',' << csv_cell(parameter.key);
  csv << ",status,wall_seconds,simulated_time,frames,accepted_steps";
  const std::vector<std::string_view> terms = final_energy_terms();
  for (std::string_view term : terms) csv << ",final_" << term;
  csv << '\n';
  for (const SweepRun& run : runs) {
    const SweepRunStatus status = read_run_status(out, run);
    csv << run.index << ',' << run.folder;
    for (const auto& [key, value] : run.assignments) csv << ',' << csv_cell(value);
    const json& summary = status.summary;
    csv << ',' << to_string(status.state) << ',' << number_cell(at_path(summary, {"timings", "wall_seconds"})) << ','
        << number_cell(at_path(summary, {"simulated_time"})) << ',' << number_cell(at_path(summary, {"frames"})) << ','
        << number_cell(at_path(summary, {"integrator", "accepted_steps"}));
    for (std::string_view term : terms) csv << ',' << number_cell(at_path(summary, {"energy", "final", term}));
    csv << '\n';
  }
  write_text_atomically(out / kIndexFile, csv.str());
}

}  // namespace clothsim
