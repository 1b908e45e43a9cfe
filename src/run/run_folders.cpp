#include "run/run_folders.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <fstream>
#include <string_view>
#include <system_error>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "run/run_checkpoints.h"
#include "run/run_writer.h"

namespace clothsim {
namespace {

namespace fs = std::filesystem;
constexpr std::string_view kPartialMarker = ".partial-";

[[noreturn]] void refuse(const std::string& reason) { throw InputError("--resume", "", reason); }

// The pid of "<name>.partial-<pid>", or 0 when `folder`'s name is not of that form.
pid_t partial_pid(const fs::path& folder) {
  const std::string name = folder.filename().string();
  const std::size_t at = name.rfind(kPartialMarker);
  if (at == std::string::npos || at == 0) return 0;
  const std::string digits = name.substr(at + kPartialMarker.size());
  if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return 0;
  return static_cast<pid_t>(std::stol(digits));
}

// True while process `pid` exists (EPERM: it exists but is another user's).
bool process_alive(pid_t pid) { return ::kill(pid, 0) == 0 || errno == EPERM; }

// summary.json's "status" of a finished run folder, or "" when there is none.
std::string finished_status(const fs::path& folder) {
  std::ifstream in(folder / RunWriter::kSummaryFile);
  if (!in) return {};
  const nlohmann::json summary = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!summary.is_object() || !summary.contains("status") || !summary["status"].is_string()) return {};
  return summary["status"].get<std::string>();
}

}  // namespace

std::string default_output_folder(const SceneSpec& spec) {
  std::string name;
  for (char c : spec.name) {
    const bool safe =
        (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.';
    name += safe ? c : '_';
  }
  if (name.empty() || name.find_first_not_of('.') == std::string::npos) name = "run";
  std::string folder = "out/";
  folder += name;
  return folder;
}

ResumeTarget find_resume_target(const std::string& path) {
  std::error_code error;
  fs::path given = fs::path(path).lexically_normal();
  if (!given.empty() && !given.has_filename()) given = given.parent_path();
  if (!fs::exists(given, error)) refuse(path + " does not exist");

  ResumeTarget target;
  fs::path first;  // an explicitly named checkpoint file
  if (fs::is_regular_file(given, error)) {
    if (given.parent_path().filename() != kCheckpointFolder) {
      refuse(path + " is not a checkpoint: expected a file in a run's " + std::string(kCheckpointFolder) + "/ folder");
    }
    first = given;
    target.folder = given.parent_path().parent_path();
  } else {
    target.folder = given;
  }
  if (target.folder.empty()) target.folder = ".";
  if (!fs::exists(target.folder / RunWriter::kSceneFile, error)) {
    refuse(target.folder.string() + " is not the output folder of a clothsim run (it has no " +
           std::string(RunWriter::kSceneFile) + ")");
  }

  if (const pid_t pid = partial_pid(target.folder); pid > 0) {
    if (pid == ::getpid() || process_alive(pid)) {
      refuse(target.folder.string() + " is still being written by process " + std::to_string(pid) +
             "; wait for it to end (or stop it) before resuming");
    }
    const std::string name = target.folder.filename().string();
    target.out = target.folder.parent_path() / name.substr(0, name.rfind(kPartialMarker));
  } else {
    const std::string status = finished_status(target.folder);
    if (status == "completed" || status == "at_rest") {
      refuse(target.folder.string() + " is complete (status \"" + status + "\"): there is nothing to resume");
    }
    if (status == "failed") {
      refuse(target.folder.string() +
             " ended with status \"failed\": resumed from a checkpoint it would fail the "
             "same way (summary.json has the diagnosis); change the scene and run it again");
    }
    target.out = target.folder;
  }

  target.checkpoints = list_run_checkpoints(target.folder);
  if (!first.empty()) {
    std::vector<fs::path> ordered{first};
    bool older = false;
    for (const fs::path& candidate : target.checkpoints) {
      if (older) ordered.push_back(candidate);
      if (fs::equivalent(candidate, first, error)) older = true;
    }
    target.checkpoints = std::move(ordered);
  }
  if (target.checkpoints.empty()) {
    refuse(target.folder.string() +
           " has no checkpoints: the run was started without --checkpoint-every (or died "
           "before its first); run it again, with --checkpoint-every SECONDS");
  }
  return target;
}

std::vector<LeftoverRun> find_partial_runs(const fs::path& out) {
  std::vector<LeftoverRun> partials;
  const fs::path normal = out.lexically_normal();
  fs::path parent = normal.parent_path();
  const std::string prefix = normal.filename().string() + std::string(kPartialMarker);
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(parent.empty() ? fs::path(".") : parent, error)) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with(prefix) || !entry.is_directory(error)) continue;
    const pid_t pid = partial_pid(entry.path());
    if (pid <= 0 || pid == ::getpid()) continue;
    partials.push_back(
        LeftoverRun{parent / name, pid, !list_run_checkpoints(entry.path()).empty(), process_alive(pid)});
  }
  return partials;
}

std::vector<LeftoverRun> find_leftover_runs(const fs::path& out) {
  std::vector<LeftoverRun> leftovers = find_partial_runs(out);
  std::erase_if(leftovers, [](const LeftoverRun& run) { return run.alive; });
  return leftovers;
}

void write_text_atomically(const fs::path& path, const std::string& text) {
  const fs::path temporary = path.string() + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw OutputError(temporary.string() + ": cannot write");
  }
  std::error_code error;
  fs::rename(temporary, path, error);
  if (error) {
    fs::remove(temporary, error);
    throw OutputError(path.string() + ": cannot write: " + error.message());
  }
}

}  // namespace clothsim
