// The checkpoints of a run (`clothsim run --checkpoint-every`, docs/cli.md "Checkpoints and
// resume"): when they are written, what they hold besides the simulation, and which one a resumed
// run starts from.
//
// A checkpoint is taken after an output frame, when the streamed files have just been handed to
// the operating system (RunWriter::flush), so it names a point where the output folder is whole:
// frames 0 .. k in positions.npy, velocities.npy, energy.csv and the exports. A run killed at any
// moment after it leaves files that hold at least those frames (and maybe more, which the resumed
// run cuts off and writes again, identically). Each checkpoint is one file,
// checkpoints/frame_<k>.ckpt inside the output folder (the partial folder while the run goes
// on), written atomically (io/checkpoint.h); the newest kKeptCheckpoints are kept, so that when
// the newest is damaged (a disk error, a truncation the atomic write cannot prevent) the one
// before it is still there.
//
// A resumed run starts from the newest checkpoint that passes its checks, saying which ones it
// passed over and why; its output from there on is the uninterrupted run's, bit for bit, because
// the checkpoint holds everything the next step depends on (sim/simulation.h, transfer_state).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/state_archive.h"
#include "run/run_writer.h"
#include "sim/simulation.h"

namespace clothsim {

inline constexpr std::string_view kCheckpointFolder = "checkpoints";
inline constexpr std::size_t kKeptCheckpoints = 2;

// What a run's checkpoint holds besides the simulation.
struct RunCheckpoint {
  RunWriter::Progress writer;      // the output files' frames and lengths
  std::uint64_t quiet_frames = 0;  // --until-rest: quiet frames in a row so far
  double wall_seconds = 0.0;       // wall time the run has taken so far, in every process, s
  std::string command_line;        // the command that began the run
  std::string options;             // the application's own settings, as JSON text (the picture flags)
  std::string scene;               // the scene as run (scene_to_json), to check it against the folder's
};

// Saves or restores `run`'s fields.
void transfer_run_checkpoint(StateArchive& archive, RunCheckpoint& run);

// "frame_000120.ckpt".
std::string checkpoint_file_name(std::uint64_t frame);

// Writes the checkpoint of `simulation` after output frame run.writer.frames - 1 into
// `folder`/checkpoints/, then deletes all but the newest kKeptCheckpoints. Returns its path.
// Throws std::runtime_error naming the path on an I/O failure.
std::filesystem::path write_run_checkpoint(const std::filesystem::path& folder, RunCheckpoint run,
                                           Simulation& simulation);

// The checkpoint files in `folder`/checkpoints/, newest (highest frame) first; none if there is no
// such folder.
std::vector<std::filesystem::path> list_run_checkpoints(const std::filesystem::path& folder);

// Deletes the temporary files of checkpoint writes that a killed run left unfinished in
// `folder`/checkpoints/ (io/checkpoint.h names them ".<name>.tmp-<pid>").
void discard_unfinished_checkpoints(const std::filesystem::path& folder);

// Restores `simulation` and `run` from the first of `candidates` (newest first) that passes its
// checks (io/checkpoint.h); for each one passed over, calls `skipped` with the reason. Returns the
// one used. Throws CheckpointError when none passes, or when the one that passes does not fit the
// simulation (a checkpoint of another scene); the simulation is then unusable.
std::filesystem::path load_run_checkpoint(std::span<const std::filesystem::path> candidates, Simulation& simulation,
                                          RunCheckpoint& run, const std::function<void(const std::string&)>& skipped);

}  // namespace clothsim
