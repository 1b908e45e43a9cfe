// A run of a scene into its output folder, frame by frame: what `clothsim run` does and what the
// Python module's clothsim.run() does, one driver for both, so the two write the same folder.
//
// run_scene(spec, options), in order (everything that can be wrong with the input is refused
// before anything is created):
//   1. the picture settings (run/render_plan.h) and the memory check (run/run_memory.h), then the model
//      (build_model: InputError when it cannot be built), the output folder (RunWriter's
//      constructor: InputError) and the pictures' OpenGL context and ffmpeg (OutputError);
//   2. frame 0 (the initial state), then frame k = 1 .. last_frame(spec.output), each the state at
//      frame_time(k, fps), written as it comes (run/run_writer.h, the pictures of
//      run/run_recorder.h), with checkpoints every output.checkpoint_every (run/run_checkpoints.h);
//      until_rest stops early once the sheet is at rest, the observer's interrupted() after any
//      complete frame, a failed simulation at its last good frame;
//   3. the pictures finished, summary.json written and the folder renamed into place, whatever
//      the status; the partial folders of earlier runs that died are deleted when the run
//      completed or came to rest.
// resume_run(path, options) goes on with a run from its newest good checkpoint instead
// (docs/cli.md, "Checkpoints and resume"): the result is the uninterrupted run's, bit for bit.
//
// Failures: bad input throws InputError and writes nothing; an output failure throws OutputError
// and leaves nothing (the partial folder is removed); a failed simulation is not an exception: the
// folder is finished with status "failed" and the result says so. The caller (the command, the
// Python module) turns these into exit codes or exceptions, and reports through a RunObserver.
//
// The frame times: the simulation advances to frame_time(k, fps) = k / fps, one division of exact
// integers, and so does anyone who steps a scene frame by frame (make_simulation(spec), then
// advance_to(frame_time(k, fps)) for k = 1, 2, ...): the states are the run's, bit for bit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "run/render_plan.h"
#include "run/run_writer.h"
#include "scene/scene.h"
#include "sim/memory_estimate.h"
#include "sim/simulation.h"

namespace clothsim {

// The simulated time of output frame `frame` at `fps` frames per second, s: frame / fps.
double frame_time(std::uint64_t frame, int fps);
// The last output frame of a run with these settings: round(duration * fps). Frames 0 .. this are
// written (fewer when the run stops early).
std::uint64_t last_frame(const OutputSettings& output);
// The scene's exports fit their size limits (RunExports::check_sizes) for all its frames (an
// until_rest run may stop sooner): run_scene() and resume_run() check it before anything is
// written, `clothsim validate` too. Throws InputError.
void check_export_sizes(const SceneSpec& spec);

// What a caller hears of a run while it goes on. Every member has a default that does nothing.
// Called on the thread that called run_scene() or resume_run().
class RunObserver {
 public:
  virtual ~RunObserver() = default;
  // A message for the user, one line without the program's name or a newline: "warning: ...",
  // "note: ...", "deleted ...". `notice` is informational (the command's --quiet hides it),
  // `warning` is always shown.
  virtual void notice(const std::string& message);
  virtual void warning(const std::string& message);
  // The scene fits `limit` (run/run_memory.h), checked before anything is built: the command caps
  // the process's growth here (apps/clothsim/memory_check.h), a limit a library leaves alone.
  virtual void memory_checked(const MemoryLimit& limit);
  // Before the first frame is simulated: the run ends at simulated time `end_time`, s, at the latest.
  virtual void frames_begin(double end_time);
  // After each frame written: the simulated time and the accepted steps so far.
  virtual void frame_done(double time, std::uint64_t accepted_steps);
  // After the last frame, before the pictures and the folder are finished.
  virtual void frames_end();
  // Polled before each frame: true stops the run with status interrupted (after a checkpoint,
  // when the run takes them).
  virtual bool interrupted();
};

struct RunOptions {
  std::filesystem::path out;         // the output folder; empty: default_output_folder(spec)
  std::string out_source = "--out";  // what named `out`, in messages
  RunInfo info;                      // the version and the command line, for summary.json
  RenderFlags render;                // the pictures (run/render_plan.h)
  RunObserver* observer = nullptr;   // none: nothing reported, never interrupted
  // The most memory the run may use (run/run_memory.h): a scene whose estimate is above it is
  // refused before its model is built. Unset: 90 % of the memory available.
  std::optional<std::uint64_t> max_memory;
  std::string max_memory_source = "--max-memory";  // what gave max_memory, in messages
  // resume_run(): the picture settings from the ones the run began with (kept in its
  // checkpoints); unset: those, unchanged.
  std::function<RenderFlags(const RenderFlags& stored)> resumed_render;
  // The run report, report.html, written into the finished folder (run/run_report.h), whatever
  // the status; a build without the report refuses it before the run.
  bool report = false;
  std::string report_source = "--report";  // what asked for it, in messages
};

// How a run ended and what it wrote.
struct RunResult {
  RunStatus status = RunStatus::completed;
  SceneSpec scene;                         // as run
  std::filesystem::path out;               // the finished output folder
  std::size_t frames = 0;                  // frames written, frame 0 included
  double last_time = 0.0;                  // s, of the last frame written
  EnergyBalance initial_energy;            // at frame 0
  EnergyBalance last_energy;               // at the last frame written
  double wall_seconds = 0.0;               // the run's wall time (for a resumed run, in every process), s
  double output_seconds = 0.0;             // of which writing the data files, s
  std::string picture_files;               // "final.png and animation.mp4", "" for none
  bool pictures = false;                   // whether pictures were made
  long picture_frames = 0;                 // frames rendered
  double picture_seconds = 0.0;            // wall time rendering and encoding, s
  std::string picture_description;         // size and OpenGL renderer
  std::unique_ptr<Simulation> simulation;  // at the last frame written; failure() has a failed run's diagnosis
  std::filesystem::path resumed_from;      // resume_run(): the checkpoint it went on from
  std::filesystem::path report;            // report.html, where RunOptions::report asked for it
};

// Runs `spec` (valid: validate_scene) into its output folder (see the top of this file).
RunResult run_scene(const SceneSpec& spec, const RunOptions& options);

// Goes on with the run `path` names (run/run_folders.h, find_resume_target) from its newest good
// checkpoint; options.out is not used (the run's folder is). Throws InputError, naming --resume,
// when there is nothing to resume there.
RunResult resume_run(const std::string& path, const RunOptions& options);

}  // namespace clothsim
