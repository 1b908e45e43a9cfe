// The output folder of one run, written so that no half-written output is ever seen at its path.
//
// A run's folder holds (docs/cli.md has the columns and keys):
//   positions.npy    float64 [frames, particles, 3], m; frame 0 is the initial state
//   velocities.npy   float64 [frames, particles, 3], m/s
//   energy.csv       one row per frame: energies, works, balance error, step counts (run/energy_table.h)
//   summary.json     version, command line, status, diagnosis, scene, counts, statistics, timings
//                    (run/run_summary.h)
//   final.obj        the sheet at the last frame written, split along its tears (model/sheet_mesh.h)
//   scene.json       the scene as run; `clothsim run <folder>/scene.json` reproduces the run
//   connectors.npy            int32 [connectors, 2]: the particles of each connector, in index order
//   connector_break_time.npy  float64 [connectors], s: the simulated time at which the connector
//                             broke (the end of the step after which it broke), +inf if it never did
//   connector_rest_length.npy float64 [connectors], m: each connector's rest length at the end
//                             (changed by yielding; a broken connector's stays as it broke)
// These let a reader rebuild any frame's live connectors and so its torn mesh (whose split
// vertices sit half a rest length along a broken connector, model/sheet_mesh.h) without storing
// the mask per frame: connector e is intact at frame k iff break_time[e] > time[k].
// With the scene's output.export, also the files for other tools of run/run_exports.h
// (animation.pc2 and rest.obj, frames/frame_NNNNNN.obj, streamed frame by frame like the arrays;
// final.glb, written at the end like final.obj).
//
// Everything is written into a sibling folder `<out>.partial-<pid>` and renamed to `<out>` by
// finish(), so that a reader sees either the previous folder or the complete new one. On Linux the
// replacement of an existing folder is one renameat2(RENAME_EXCHANGE); elsewhere the old folder is
// first renamed aside. A run that dies with an exception before finish() leaves nothing behind:
// the destructor removes the partial folder. A failed *simulation* is not such a death: the tool
// still calls finish() with status "failed", and the frames up to the last good one are kept.
//
// Frames are streamed to disk as they come (NpyWriter), never held in memory: a trajectory of a
// large sheet does not fit. Only the last frame's positions are kept, for final.obj (and
// final.glb), and one break time per connector.
//
// Rejected alternatives: writing straight into `<out>` (an interrupted or failed run leaves a mix
// of old and new files), and deleting an existing `<out>` up front (a typo in --out could delete
// an unrelated folder; we replace only folders that a clothsim run wrote, recognised by the
// "clothsim_version" key of their summary.json).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/vec3.h"
#include "io/npy.h"
#include "run/run_exports.h"
#include "run/run_status.h"
#include "scene/scene.h"
#include "sim/simulation.h"

namespace clothsim {

// What the writer records about the program that made the run.
struct RunInfo {
  std::string version;       // summary.json "clothsim_version"; its presence marks a clothsim folder
  std::string command_line;  // summary.json "command_line", as the user typed it (the first, for a resumed run)
};

class RunWriter {
 public:
  // Names of the files in a finished folder, in the order they are described above.
  static constexpr std::string_view kPositionsFile = "positions.npy";
  static constexpr std::string_view kVelocitiesFile = "velocities.npy";
  static constexpr std::string_view kEnergyFile = "energy.csv";
  static constexpr std::string_view kSummaryFile = "summary.json";
  static constexpr std::string_view kFinalMeshFile = "final.obj";
  static constexpr std::string_view kSceneFile = "scene.json";
  static constexpr std::string_view kConnectorsFile = "connectors.npy";
  static constexpr std::string_view kBreakTimeFile = "connector_break_time.npy";
  static constexpr std::string_view kRestLengthFile = "connector_rest_length.npy";

  // Checks that `out` may receive the run and creates nothing: `out` must not exist, or be a
  // folder holding a summary.json with a "clothsim_version" key (a previous run, which finish()
  // replaces). Otherwise throws InputError naming `source` (the flag that gave the path). Call it
  // before the simulation starts, so that bad input never costs a run.
  explicit RunWriter(const std::filesystem::path& out, RunInfo info, const std::string& source = "--out");
  // Removes the partial folder unless finish() ran; never throws.
  ~RunWriter();

  RunWriter(const RunWriter&) = delete;
  RunWriter& operator=(const RunWriter&) = delete;

  // Creates the partial folder (and `out`'s parent folders), writes scene.json, and opens the
  // streamed files. The simulation must be at its initial state: its energies are the "initial"
  // ones of summary.json. Throws OutputError.
  void begin(const SceneSpec& scene, const Simulation& simulation);

  // Appends the simulation's current state as the next frame (frame 0 first: the initial state).
  // Throws OutputError.
  void write_frame(const Simulation& simulation);

  // Where the streamed files stand, for a checkpoint (run/run_checkpoints.h): a resumed run cuts
  // them back to this and goes on.
  struct Progress {
    std::uint64_t frames = 0;        // frames written, frame 0 included
    std::uint64_t energy_bytes = 0;  // length of energy.csv after them
    EnergyBalance initial;           // summary.json's "initial" energies
  };
  // Hands the streamed files' buffers to the operating system (so a process killed from here on
  // loses none of these frames) and says where they stand. Throws OutputError.
  Progress flush();
  // Instead of begin(): goes on with a run from a checkpoint. `from` is the run's folder: a
  // partial folder left by a run that died (renamed to partial()) or a finished one (copied to
  // partial(), so that `out` stays whole until finish() replaces it). The streamed files are cut
  // back to `progress`, the files finish() writes are removed, and the next frame written is
  // frame progress.frames. The simulation must be restored to that frame's state. summary.json
  // "resumed" records `command_line` (the resuming command) and the time resumed from. Throws
  // OutputError.
  void resume(const std::filesystem::path& from, const SceneSpec& scene, const Simulation& simulation,
              const Progress& progress, std::string command_line);

  // Records a file that someone else wrote into partial() (e.g. the pictures of a run) under
  // summary.json "files", after the writer's own; `details` describes it (an object).
  void add_file(std::string name, nlohmann::ordered_json details);

  // Writes final.obj (the last frame) and summary.json, closes every file and renames the
  // folder to `out`, replacing a previous run there. `wall_seconds` is the run's wall time
  // (summary.json "timings"). A failed simulation's diagnosis comes from simulation.failure().
  // Throws OutputError; the partial folder is then removed.
  void finish(const Simulation& simulation, RunStatus status, double wall_seconds);

  const std::filesystem::path& out() const { return out_; }
  const std::filesystem::path& partial() const { return partial_; }
  std::size_t frames() const { return frames_; }
  // Energies at begin() and at the last frame written, and that frame's time (s).
  const EnergyBalance& initial_energy() const { return initial_energy_; }
  const EnergyBalance& last_energy() const { return last_energy_; }
  double last_time() const { return last_time_; }
  // Wall time spent writing output so far, s.
  double output_seconds() const { return output_seconds_; }
  // True when `out` held a previous run that finish() replaces (or replaced).
  bool replaces_previous_run() const { return replace_existing_; }

  // The most memory the writer holds at once for a run of `frames` frames of the lattice of
  // `counts` writing `exports` (run/run_memory.h): the last frame's positions throughout, and at
  // the end the mesh of final.obj (the connector table at the start is smaller), with the
  // exports' own.
  static std::size_t bytes_for(const LatticeCounts& counts, std::size_t frames, std::span<const ExportFormat> exports);

 private:
  void close_files();
  void install();
  void discard() noexcept;

  std::filesystem::path out_;
  std::filesystem::path partial_;  // `<out>.partial-<pid>`
  RunInfo info_;
  std::string resumed_by_;   // resume(): the resuming command line
  double resumed_at_ = 0.0;  // resume(): the time resumed from, s
  bool replace_existing_ = false;
  bool begun_ = false;
  bool finished_ = false;

  std::optional<NpyWriter> positions_;
  std::optional<NpyWriter> velocities_;
  std::FILE* energy_file_ = nullptr;
  std::optional<RunExports> exports_;  // when the scene asks for any

  SceneSpec scene_;  // the scene as run, for summary.json
  EnergyBalance initial_energy_;
  EnergyBalance last_energy_;        // of the last frame written
  double last_time_ = 0.0;           // s, of the last frame written
  std::vector<Vec3> last_position_;  // [particles], m, of the last frame written
  std::vector<std::pair<std::string, nlohmann::ordered_json>> extra_files_;  // add_file()
  std::size_t frames_ = 0;
  double output_seconds_ = 0.0;
};

}  // namespace clothsim
