#include "run/run_checkpoints.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <optional>
#include <system_error>

#include "core/record_fields.h"
#include "io/checkpoint.h"

namespace clothsim {
namespace {

namespace fs = std::filesystem;

// The frame of "frame_000120.ckpt", or false for any other name.
bool parse_checkpoint_name(const std::string& name, std::uint64_t& frame) {
  constexpr std::string_view kPrefix = "frame_";
  constexpr std::string_view kSuffix = ".ckpt";
  if (name.size() <= kPrefix.size() + kSuffix.size() || !name.starts_with(kPrefix) || !name.ends_with(kSuffix)) {
    return false;
  }
  const std::string digits = name.substr(kPrefix.size(), name.size() - kPrefix.size() - kSuffix.size());
  if (digits.size() > 18 || !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return false;
  }
  frame = std::stoull(digits);
  return true;
}

}  // namespace

void transfer_run_checkpoint(StateArchive& archive, RunCheckpoint& run) {
  archive.value("run.frames", run.writer.frames);
  archive.value("run.energy_bytes", run.writer.energy_bytes);
  transfer_fields(archive, "run.initial", run.writer.initial);
  archive.value("run.quiet_frames", run.quiet_frames);
  archive.value("run.wall_seconds", run.wall_seconds);
  archive.text("run.command_line", run.command_line);
  archive.text("run.options", run.options);
  archive.text("run.scene", run.scene);
  if (archive.loading() && run.writer.frames == 0) {
    throw CheckpointError("field 'run.frames' is 0: a checkpoint follows frame 0 at least");
  }
}

std::string checkpoint_file_name(std::uint64_t frame) {
  std::array<char, 40> name{};
  std::snprintf(name.data(), name.size(), "frame_%06llu.ckpt", static_cast<unsigned long long>(frame));
  return name.data();
}

fs::path write_run_checkpoint(const fs::path& folder, RunCheckpoint run, Simulation& simulation) {
  const fs::path directory = folder / kCheckpointFolder;
  fs::create_directories(directory);
  fs::path path = directory / checkpoint_file_name(run.writer.frames - 1);
  write_checkpoint(path, [&](StateArchive& archive) {
    transfer_run_checkpoint(archive, run);
    simulation.transfer_state(archive);
  });
  const std::vector<fs::path> all = list_run_checkpoints(folder);
  for (std::size_t k = kKeptCheckpoints; k < all.size(); ++k) {
    std::error_code ignored;
    fs::remove(all[k], ignored);
  }
  return path;
}

std::vector<fs::path> list_run_checkpoints(const fs::path& folder) {
  std::vector<std::pair<std::uint64_t, fs::path>> found;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder / kCheckpointFolder, error)) {
    std::uint64_t frame = 0;
    if (entry.is_regular_file(error) && parse_checkpoint_name(entry.path().filename().string(), frame)) {
      found.emplace_back(frame, entry.path());
    }
  }
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<fs::path> paths;
  for (auto& [frame, path] : found) paths.push_back(std::move(path));
  return paths;
}

void discard_unfinished_checkpoints(const fs::path& folder) {
  std::error_code error;
  std::vector<fs::path> unfinished;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder / kCheckpointFolder, error)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with(".") && name.find(".tmp-") != std::string::npos) unfinished.push_back(entry.path());
  }
  for (const fs::path& path : unfinished) fs::remove(path, error);
}

fs::path load_run_checkpoint(std::span<const fs::path> candidates, Simulation& simulation, RunCheckpoint& run,
                             const std::function<void(const std::string&)>& skipped) {
  for (const fs::path& path : candidates) {
    std::optional<CheckpointReader> reader;
    try {
      reader.emplace(path);  // the whole file is checked here, before anything is applied
    } catch (const CheckpointError& error) {
      skipped(error.what());
      continue;
    }
    try {
      transfer_run_checkpoint(*reader, run);
      simulation.transfer_state(*reader);
      reader->finish();
    } catch (const CheckpointError&) {
      throw;
    } catch (const std::exception& error) {
      throw CheckpointError(path.string() + ": " + error.what());
    }
    return path;
  }
  throw CheckpointError(candidates.empty() ? std::string("no checkpoint to resume from")
                                           : "no usable checkpoint among the " + std::to_string(candidates.size()) +
                                                 " found (each was damaged: see above)");
}

}  // namespace clothsim
