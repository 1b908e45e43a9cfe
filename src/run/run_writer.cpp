// The run output folder; the layout and the no-half-written-output rule are in run_writer.h.
//
// Every failure to write becomes an OutputError carrying the system's message (which names the
// path), so the tools can tell "cannot write" (exit 3) from bad input (exit 2) and from a failed
// simulation (exit 1).
#include "run/run_writer.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <system_error>

#include "core/assert.h"
#include "core/error.h"
#include "core/timer.h"
#include "io/obj.h"
#include "model/sheet_mesh.h"
#include "run/energy_table.h"
#include "run/run_summary.h"

namespace clothsim {
namespace {

using nlohmann::json;
// summary.json keeps its keys in the order written: version and status first, details after.
using ordered_json = nlohmann::ordered_json;
namespace fs = std::filesystem;

// Turns the exception in flight into an OutputError that says what was being done.
[[noreturn]] void rethrow_as_output_error(const char* doing) {
  try {
    throw;
  } catch (const OutputError&) {
    throw;
  } catch (const std::exception& error) {
    std::string message = doing;
    message += ": ";
    message += error.what();
    throw OutputError(message);
  }
}

// A folder written by a previous clothsim run: it holds a summary.json object with the
// "clothsim_version" key.
bool is_clothsim_folder(const fs::path& folder) {
  std::error_code error;
  if (!fs::is_directory(folder, error)) return false;
  std::ifstream in(folder / RunWriter::kSummaryFile);
  if (!in) return false;
  const json summary = json::parse(in, nullptr, /*allow_exceptions=*/false);
  return summary.is_object() && summary.contains("clothsim_version");
}

void write_text_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  out.close();
  if (!out) {
    std::string message = path.string();
    message += ": cannot write file";
    if (errno != 0) {
      message += ": ";
      message += std::strerror(errno);
    }
    throw OutputError(message);
  }
}

}  // namespace

RunWriter::RunWriter(const fs::path& out, RunInfo info, const std::string& source) : info_(std::move(info)) {
  // "runs/a/" names the folder "runs/a"; ".", ".." and "/" name no new folder.
  fs::path path = out.lexically_normal();
  if (!path.empty() && !path.has_filename()) path = path.parent_path();
  const fs::path name = path.filename();
  if (path.empty() || name.empty() || name == "." || name == ".." || path == path.root_path()) {
    std::string reason = "must name an output folder, got \"";
    reason += out.string();
    reason += "\"";
    throw InputError(source, "", reason);
  }
  out_ = path;
  std::string partial_name = name.string();
  partial_name += ".partial-";
  partial_name += std::to_string(static_cast<long long>(::getpid()));
  partial_ = out_.parent_path() / partial_name;

  std::error_code error;
  const fs::file_status status = fs::symlink_status(out_, error);
  if (fs::exists(status)) {
    if (!is_clothsim_folder(out_)) {
      std::string reason = out_.string();
      reason += " exists and is not a clothsim output folder; choose another path";
      throw InputError(source, "", reason);
    }
    replace_existing_ = true;
  }
}

RunWriter::~RunWriter() {
  if (!finished_) discard();
}

void RunWriter::close_files() {
  if (positions_) positions_->close();
  if (velocities_) velocities_->close();
  if (energy_file_ != nullptr) {
    const bool failed = std::ferror(energy_file_) != 0;
    const int close_result = std::fclose(energy_file_);
    energy_file_ = nullptr;
    if (failed || close_result != 0) {
      std::string message = (partial_ / kEnergyFile).string();
      message += ": cannot write file: ";
      message += std::strerror(errno);
      throw OutputError(message);
    }
  }
}

void RunWriter::discard() noexcept {
  try {
    positions_.reset();  // closes without reporting errors
    velocities_.reset();
    exports_.reset();
    if (energy_file_ != nullptr) std::fclose(energy_file_);
    energy_file_ = nullptr;
  } catch (...) {
    // Nothing to report from a destructor; the folder is removed below either way.
  }
  if (begun_) {
    std::error_code error;
    fs::remove_all(partial_, error);
  }
}

void RunWriter::begin(const SceneSpec& scene, const Simulation& simulation) {
  CLOTHSIM_ASSERT(!begun_, "begin() is called once");
  ScopedTimer timer(output_seconds_);
  try {
    if (out_.has_parent_path()) fs::create_directories(out_.parent_path());
    // A stale partial folder of a crashed run that had our process id.
    fs::remove_all(partial_);
    fs::create_directory(partial_);
    begun_ = true;

    scene_ = scene;
    write_text_file(partial_ / kSceneFile, scene_to_json(scene).dump(2) + "\n");

    const std::size_t particles = simulation.model().particle_count();
    positions_.emplace((partial_ / kPositionsFile).string(), particles);
    velocities_.emplace((partial_ / kVelocitiesFile).string(), particles);

    const fs::path energy_path = partial_ / kEnergyFile;
    energy_file_ = std::fopen(energy_path.c_str(), "wb");
    if (energy_file_ == nullptr) {
      std::string message = energy_path.string();
      message += ": cannot create file: ";
      message += std::strerror(errno);
      throw OutputError(message);
    }
    std::fprintf(energy_file_, "%s\n", energy_table_header().c_str());

    // The connector table, once: connector e's particles, in index order (int32, which NumPy
    // indexes with directly).
    const ClothModel& model = simulation.model();
    std::vector<std::int32_t> pairs;
    pairs.reserve(2 * model.connector_count());
    for (const auto& [a, b] : model.connector_particles) {
      pairs.push_back(static_cast<std::int32_t>(a));
      pairs.push_back(static_cast<std::int32_t>(b));
    }
    const std::array<std::size_t, 2> shape = {model.connector_count(), 2};
    write_npy((partial_ / kConnectorsFile).string(), pairs, shape);

    if (!scene.output.exports.empty()) exports_.emplace(partial_, scene.output.exports, model, scene.name);
  } catch (...) {
    rethrow_as_output_error("cannot create the output folder");
  }
  initial_energy_ = simulation.energy_balance();
  last_position_.reserve(simulation.model().particle_count());
}

std::size_t RunWriter::bytes_for(const LatticeCounts& counts, std::size_t frames,
                                 std::span<const ExportFormat> exports) {
  const std::size_t last_position = counts.particles * sizeof(decltype(last_position_)::value_type);
  const std::size_t connector_table = 2 * counts.connectors * sizeof(std::int32_t);
  const std::size_t final_mesh = SheetMesh::bytes_for(counts.rows, counts.cols);
  const RunExports::Memory exported = RunExports::bytes_for(counts, frames, exports);
  return last_position + exported.held + std::max({connector_table, final_mesh, exported.peak});
}

void RunWriter::write_frame(const Simulation& simulation) {
  CLOTHSIM_ASSERT(begun_ && !finished_, "write_frame() between begin() and finish()");
  ScopedTimer timer(output_seconds_);
  const ClothState& state = simulation.state();
  const EnergyRow row = EnergyRow::of(frames_, simulation);
  try {
    positions_->append(state.position);
    velocities_->append(state.velocity);
    if (exports_) exports_->write_frame(simulation.model(), state.position, state.time);
  } catch (...) {
    rethrow_as_output_error("cannot write a frame");
  }
  const std::string line = energy_table_row(row);
  if (std::fprintf(energy_file_, "%s\n", line.c_str()) < 0) {
    std::string message = (partial_ / kEnergyFile).string();
    message += ": cannot write file: ";
    message += std::strerror(errno);
    throw OutputError(message);
  }
  last_position_.assign(state.position.begin(), state.position.end());
  last_energy_ = row.balance;
  last_time_ = state.time;
  ++frames_;
}

RunWriter::Progress RunWriter::flush() {
  CLOTHSIM_ASSERT(begun_ && !finished_, "flush() between begin() and finish()");
  ScopedTimer timer(output_seconds_);
  Progress progress;
  try {
    positions_->flush();
    velocities_->flush();
    if (exports_) exports_->flush();
    errno = 0;
    const long energy_bytes = std::fflush(energy_file_) == 0 ? std::ftell(energy_file_) : -1;
    if (energy_bytes < 0) throw std::runtime_error((partial_ / kEnergyFile).string() + ": " + std::strerror(errno));
    progress.energy_bytes = static_cast<std::uint64_t>(energy_bytes);
  } catch (...) {
    rethrow_as_output_error("cannot flush the output files");
  }
  progress.frames = frames_;
  progress.initial = initial_energy_;
  return progress;
}

void RunWriter::resume(const fs::path& from, const SceneSpec& scene, const Simulation& simulation,
                       const Progress& progress, std::string command_line) {
  CLOTHSIM_ASSERT(!begun_, "resume() instead of begin()");
  resumed_by_ = std::move(command_line);
  resumed_at_ = simulation.state().time;
  CLOTHSIM_ASSERT(progress.frames > 0, "a checkpoint follows frame 0 at least");
  ScopedTimer timer(output_seconds_);
  const std::size_t particles = simulation.model().particle_count();
  const auto frames = static_cast<std::size_t>(progress.frames);
  try {
    fs::remove_all(partial_);
    std::error_code not_there;
    if (fs::equivalent(from, out_, not_there)) {
      fs::copy(from, partial_, fs::copy_options::recursive);
    } else {
      fs::rename(from, partial_);
    }
    begun_ = true;
    scene_ = scene;
    // What finish() writes anew; a finished folder's pictures are made again from frame 0.
    for (std::string_view name : {kSummaryFile, kFinalMeshFile, kBreakTimeFile, kRestLengthFile,
                                  RunExports::kRestMeshFile, RunExports::kGlbFile, RunExports::kAnimationGlbFile,
                                  std::string_view("final.png"), std::string_view("animation.mp4")}) {
      fs::remove(partial_ / name);
    }
    positions_.emplace((partial_ / kPositionsFile).string(), particles, 3, frames);
    velocities_.emplace((partial_ / kVelocitiesFile).string(), particles, 3, frames);

    const fs::path energy_path = partial_ / kEnergyFile;
    fs::resize_file(energy_path, progress.energy_bytes);
    energy_file_ = std::fopen(energy_path.c_str(), "r+b");
    if (energy_file_ == nullptr || std::fseek(energy_file_, 0, SEEK_END) != 0) {
      throw std::runtime_error(energy_path.string() + ": cannot reopen: " + std::strerror(errno));
    }
    if (!scene.output.exports.empty()) {
      std::vector<Vec3> first(particles);
      read_npy_frame((partial_ / kPositionsFile).string(), 0, first);
      exports_.emplace(partial_, scene.output.exports, simulation.model(), scene.name, frames, first);
    }
  } catch (...) {
    rethrow_as_output_error("cannot resume the output folder");
  }
  frames_ = frames;
  initial_energy_ = progress.initial;
  last_energy_ = simulation.energy_balance();
  last_time_ = simulation.state().time;
  last_position_ = simulation.state().position;
}

void RunWriter::add_file(std::string name, nlohmann::ordered_json details) {
  extra_files_.emplace_back(std::move(name), std::move(details));
}

void RunWriter::finish(const Simulation& simulation, RunStatus status, double wall_seconds) {
  CLOTHSIM_ASSERT(begun_ && !finished_, "finish() once, after begin()");
  {
    ScopedTimer timer(output_seconds_);
    try {
      close_files();
      const ClothModel& model = simulation.model();
      if (frames_ > 0) {
        std::string comment = "scene ";
        comment += scene_.name;
        comment += ", frame ";
        comment += std::to_string(frames_ - 1);
        comment += " at t = ";
        comment += std::to_string(last_time_);
        comment += " s";
        write_obj((partial_ / kFinalMeshFile).string(), model, last_position_, comment);
      }
      const std::array<std::size_t, 1> shape = {simulation.model().connector_break_time.size()};
      write_npy((partial_ / kBreakTimeFile).string(), simulation.model().connector_break_time, shape);
      write_npy((partial_ / kRestLengthFile).string(), simulation.model().connector_rest_length, shape);
      if (exports_) exports_->finish(model, last_position_, last_time_, partial_ / kPositionsFile, scene_.output.fps);
    } catch (...) {
      rethrow_as_output_error("cannot finish the output folder");
    }
  }

  const ClothModel& model = simulation.model();
  const std::size_t particles = model.particle_count();
  const ordered_json shape = ordered_json::array({frames_, particles, 3});
  RunRecord run;
  run.version = info_.version;
  run.command_line = info_.command_line;
  run.resumed_by = resumed_by_;
  run.resumed_at = resumed_at_;
  run.status = status;
  run.scene = &scene_;
  run.frames = frames_;
  run.last_time = last_time_;
  run.initial_energy = initial_energy_;
  run.last_energy = last_energy_;
  run.wall_seconds = wall_seconds;
  run.output_seconds = output_seconds_;
  run.files = ordered_json{
      {std::string(kPositionsFile), ordered_json{{"shape", shape}, {"dtype", "float64"}, {"unit", "m"}}},
      {std::string(kVelocitiesFile), ordered_json{{"shape", shape}, {"dtype", "float64"}, {"unit", "m/s"}}},
      {std::string(kEnergyFile), ordered_json{{"rows", frames_}}},
      {std::string(kFinalMeshFile),
       ordered_json{{"frame", frames_ > 0 ? ordered_json(frames_ - 1) : ordered_json(nullptr)}}},
      {std::string(kSceneFile), ordered_json::object()},
      {std::string(kConnectorsFile),
       ordered_json{{"shape", ordered_json::array({model.connector_count(), 2})}, {"dtype", "int32"}}},
      {std::string(kBreakTimeFile),
       ordered_json{{"shape", ordered_json::array({model.connector_count()})}, {"dtype", "float64"}, {"unit", "s"}}},
      {std::string(kRestLengthFile),
       ordered_json{{"shape", ordered_json::array({model.connector_count()})}, {"dtype", "float64"}, {"unit", "m"}}}};
  if (exports_) {
    for (const auto& [name, details] : exports_->summary_files()) run.files[name] = details;
  }
  for (const auto& [name, details] : extra_files_) run.files[name] = details;
  const ordered_json summary = run_summary(run, simulation);

  ScopedTimer timer(output_seconds_);
  try {
    // The command line is whatever bytes the shell passed (a Latin-1 folder name, say), and JSON
    // holds only UTF-8: bytes that are not are written as U+FFFD rather than failing the run.
    write_text_file(partial_ / kSummaryFile,
                    summary.dump(2, ' ', false, ordered_json::error_handler_t::replace) + "\n");
    install();
  } catch (...) {
    rethrow_as_output_error("cannot finish the output folder");
  }
  finished_ = true;
}

// Renames the partial folder to `out`, replacing a previous run there.
void RunWriter::install() {
  std::error_code error;
  if (!fs::exists(fs::symlink_status(out_, error))) {
    fs::rename(partial_, out_);
    return;
  }
  // Checked again: the folder may have changed while the simulation ran.
  if (!is_clothsim_folder(out_)) {
    std::string message = out_.string();
    message += " appeared during the run and is not a clothsim output folder; not replacing it";
    throw OutputError(message);
  }
#ifdef RENAME_EXCHANGE
  // One atomic swap; the partial name then holds the previous run, which we delete.
  if (::renameat2(AT_FDCWD, partial_.c_str(), AT_FDCWD, out_.c_str(), RENAME_EXCHANGE) == 0) {
    fs::remove_all(partial_, error);
    return;
  }
  if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP) {
    throw fs::filesystem_error("cannot replace the previous run", partial_, out_,
                               std::error_code(errno, std::generic_category()));
  }
#endif
  // No atomic exchange on this system or file system: move the old run aside first.
  std::string old_name = out_.filename().string();
  old_name += ".old-";
  old_name += std::to_string(static_cast<long long>(::getpid()));
  const fs::path old = out_.parent_path() / old_name;
  fs::remove_all(old);
  fs::rename(out_, old);
  fs::rename(partial_, out_);
  fs::remove_all(old, error);
}

}  // namespace clothsim
