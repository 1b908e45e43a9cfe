// The run driver: a scene's frames into its output folder, new or resumed (run_scene.h).
#include "run/run_scene.h"

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <system_error>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/timer.h"
#include "forces/forces.h"
#include "integrators/stable_step.h"
#include "io/checkpoint.h"
#include "io/npy.h"
#include "run/run_checkpoints.h"
#include "run/run_folders.h"
#include "run/run_memory.h"
#include "run/run_recorder.h"
#include "run/run_report.h"
#include "scene/parameters.h"
#include "scene/scene_model.h"
#include "scene/scene_simulation.h"

namespace clothsim {

double frame_time(std::uint64_t frame, int fps) { return static_cast<double>(frame) / fps; }

std::uint64_t last_frame(const OutputSettings& output) {
  return static_cast<std::uint64_t>(std::llround(output.duration * output.fps));
}

void RunObserver::notice(const std::string& /*message*/) {}
void RunObserver::warning(const std::string& /*message*/) {}
void RunObserver::memory_checked(const MemoryLimit& /*limit*/) {}
void RunObserver::frames_begin(double /*end_time*/) {}
void RunObserver::frame_done(double /*time*/, std::uint64_t /*accepted_steps*/) {}
void RunObserver::frames_end() {}
bool RunObserver::interrupted() { return false; }

namespace {

// Warns when a fixed-step explicit method's step exceeds the stable step estimated from the
// stiffest springs (integrators/stable_step.h): warned, not refused (the estimate is a bound).
void warn_about_stability(const ClothModel& model, const IntegratorSettings& integrator, RunObserver& observer) {
  const StableStep stable = estimate_stable_step(model, integrator.kind);
  if (!(integrator.time_step > stable.step)) return;
  std::ostringstream message;
  message << "warning: integrator.time_step = " << format_number(integrator.time_step) << " s is above "
          << to_string(integrator.kind) << "'s estimated stable step, " << std::setprecision(3) << stable.step
          << " s (the stiffest springs are at " << model.describe_particle(stable.particle)
          << "); the run may blow up. A smaller --time-step, or --integrator rkf45 or implicit-euler, avoids it.";
  observer.notice(message.str());
}

// A run that asks for its report in a build without one is refused before it starts, not after.
void check_report_available(const RunOptions& options) {
  if (options.report && !report_available()) {
    throw InputError(options.report_source, "",
                     "this clothsim was built without the run report: three.js was not found at build time in "
                     "web/node_modules (scripts/install-deps.sh installs it with npm ci; then build again)");
  }
}

// The partial folders earlier runs into the same folder left when they died, reported at the
// start; a run that completes replaces them.
void report_leftovers(const std::vector<LeftoverRun>& leftovers, RunObserver& observer) {
  for (const LeftoverRun& leftover : leftovers) {
    std::string message = "note: an earlier run (process " + std::to_string(leftover.pid) + ") died and left " +
                          leftover.folder.string() + "; ";
    if (leftover.has_checkpoint) {
      message +=
          "to continue it instead, stop this run and use: clothsim run --resume " + leftover.folder.string() + ". ";
    }
    message += "It is deleted when this run completes.";
    observer.notice(message);
  }
}

void remove_leftovers(const std::vector<LeftoverRun>& leftovers, RunObserver& observer) {
  for (const LeftoverRun& leftover : leftovers) {
    std::error_code error;
    std::filesystem::remove_all(leftover.folder, error);
    observer.notice(std::string(error ? "could not delete " : "deleted ") + leftover.folder.string() +
                    ", left by the run that died");
  }
}

// The frame loop's checkpoints (run/run_checkpoints.h): after the first frame at least
// output.checkpoint_every after the previous one (or the run's start), and after the last frame of
// an interrupted run, so that it resumes where it stopped.
class Checkpointer {
 public:
  Checkpointer(const SceneSpec& spec, RunCheckpoint& run, const Stopwatch& wall)
      : every_(spec.output.checkpoint_every), run_(run), wall_(wall), wall_before_(run.wall_seconds) {
    // A resumed run's last checkpoint was at its first frame's predecessor.
    last_time_ = frame_time(run.writer.frames > 0 ? run.writer.frames - 1 : 0, spec.output.fps);
  }
  bool enabled() const { return every_ > 0.0; }
  // After a frame at `time`: a checkpoint when one is due.
  void after_frame(RunWriter& writer, Simulation& simulation, double time) {
    // The relative margin keeps a frame that lands on the interval by rounding from waiting a frame.
    if (enabled() && time - last_time_ >= every_ * (1.0 - 1e-9)) write(writer, simulation);
  }
  // Before an early end: a checkpoint of the last frame, unless it has one.
  void before_end(RunWriter& writer, Simulation& simulation) {
    if (enabled() && written_frames_ != writer.frames() && !simulation.failure()) write(writer, simulation);
  }

 private:
  void write(RunWriter& writer, Simulation& simulation) {
    run_.writer = writer.flush();
    run_.wall_seconds = wall_before_ + wall_.seconds();
    try {
      write_run_checkpoint(writer.partial(), run_, simulation);
    } catch (const std::exception& error) {
      throw OutputError(std::string("cannot write a checkpoint: ") + error.what());
    }
    last_time_ = simulation.state().time;
    written_frames_ = writer.frames();
  }

  double every_;
  RunCheckpoint& run_;
  const Stopwatch& wall_;
  double wall_before_;
  double last_time_ = 0.0;
  std::size_t written_frames_ = 0;
};

// The frames from run.writer.frames (1 for a new run: frame 0 is written) to the end, each written
// as it comes, with checkpoints. Returns how the run ended.
RunStatus simulate_frames(const SceneSpec& spec, RunObserver& observer, Simulation& simulation, RunWriter& writer,
                          RunRecorder& recorder, RunCheckpoint& run, const Stopwatch& wall) {
  Checkpointer checkpointer(spec, run, wall);
  const int fps = spec.output.fps;
  const std::uint64_t last = last_frame(spec.output);
  observer.frames_begin(frame_time(last, fps));
  RunStatus status = RunStatus::completed;
  // until_rest: frames in a row whose kinetic energy is below the threshold, and how many make
  // rest_duration (the first such frame and the one rest_duration later, and all between).
  const auto rest_frames = static_cast<std::uint64_t>(std::llround(spec.output.rest_duration * fps)) + 1;
  for (std::uint64_t frame = run.writer.frames; frame <= last; ++frame) {
    if (observer.interrupted()) {
      status = RunStatus::interrupted;
      break;
    }
    if (!simulation.advance_to(frame_time(frame, fps))) {
      status = RunStatus::failed;
      break;
    }
    writer.write_frame(simulation);
    recorder.frame(simulation.model(), simulation.state().position, simulation.state().time);
    observer.frame_done(simulation.state().time, simulation.integrator_stats().accepted_steps);
    if (spec.output.until_rest) {
      const bool quiet =
          kinetic_energy(simulation.model(), simulation.state().velocity) < spec.output.rest_kinetic_energy;
      run.quiet_frames = quiet ? run.quiet_frames + 1 : 0;
      if (run.quiet_frames >= rest_frames) {
        status = RunStatus::at_rest;
        break;
      }
    }
    checkpointer.after_frame(writer, simulation, simulation.state().time);
  }
  if (status == RunStatus::interrupted) checkpointer.before_end(writer, simulation);
  observer.frames_end();
  return status;
}

// The end of a run, new or resumed: the pictures and the folder finished.
RunResult finish_run(const SceneSpec& spec, const RenderPlan& plan, std::unique_ptr<Simulation> simulation,
                     RunWriter& writer, RunRecorder& recorder, RunStatus status, double wall_seconds, bool report) {
  recorder.finish(writer);
  writer.finish(*simulation, status, wall_seconds);
  RunResult result;
  result.status = status;
  result.scene = spec;
  result.out = writer.out();
  result.frames = writer.frames();
  result.last_time = writer.last_time();
  result.initial_energy = writer.initial_energy();
  result.last_energy = writer.last_energy();
  result.wall_seconds = wall_seconds;
  result.output_seconds = writer.output_seconds();
  result.picture_files = describe_render_outputs(plan);
  result.pictures = recorder.active();
  result.picture_frames = recorder.frames();
  result.picture_seconds = recorder.seconds();
  result.picture_description = recorder.description();
  result.simulation = std::move(simulation);
  if (report) result.report = write_run_report(result.out);
  return result;
}

// The scene fits the memory the run may use (run/run_memory.h): checked from its shape, before
// its model is built; make_simulation() then has nothing more to check. Throws ResourceError.
MemoryAllowance check_run_memory(const SceneSpec& spec, const RenderPlan& plan, const RunOptions& options,
                                 RunObserver& observer) {
  const MemoryLimit limit = memory_limit(options.max_memory, options.max_memory_source);
  check_memory(estimate_run_memory(spec, plan), limit, "the scene", options.max_memory_source);
  observer.memory_checked(limit);
  return MemoryAllowance{options.max_memory, options.max_memory_source, true};
}

// The scene's backend has its device, with the memory for the scene (sim/backend.h): checked from
// the lattice's shape, before its model is built. Throws BackendError.
void check_backend_fits(const SceneSpec& spec) {
  const SimulationShape shape = simulation_shape(spec);
  clothsim::check_backend_fits(shape.counts, shape.anchors, spec.integrator, spec.backend, spec.colliders.size(),
                               spec.collision.self);
}

}  // namespace

void check_export_sizes(const SceneSpec& spec) {
  RunExports::check_sizes(simulation_shape(spec).counts, last_frame(spec.output) + 1, spec.output.exports);
}

RunResult run_scene(const SceneSpec& spec, const RunOptions& options) {
  RunObserver silent;
  RunObserver& observer = options.observer != nullptr ? *options.observer : silent;
  // 1. Input: pictures, memory, model, output folder. Bad input throws InputError here, before
  //    anything exists on disk.
  const std::shared_ptr<const RenderPlan> render_plan = parse_render_flags(options.render);
  // A scene too large is refused before its model is built, and so is one without its device.
  const MemoryAllowance memory = check_run_memory(spec, *render_plan, options, observer);
  check_export_sizes(spec);
  check_backend_fits(spec);
  check_report_available(options);
  ClothModel model = build_model(spec);
  RunWriter writer(options.out.empty() ? std::filesystem::path(default_output_folder(spec)) : options.out, options.info,
                   options.out_source);
  // The OpenGL context and ffmpeg are checked now, before the run: a machine that cannot make
  // pictures fails at once (OutputError, suggesting --render none), not after a long simulation.
  RunRecorder recorder(render_plan, model);
  warn_about_stability(model, scene_integrator(spec), observer);
  const std::vector<LeftoverRun> leftovers = find_leftover_runs(writer.out());
  report_leftovers(leftovers, observer);

  // 2. The run.
  const Stopwatch wall;
  std::unique_ptr<Simulation> simulation = make_unique_simulation(spec, std::move(model), memory);
  writer.begin(spec, *simulation);
  writer.write_frame(*simulation);
  // Pictures go into the partial folder too, so they appear (or not) with everything else.
  recorder.begin(writer.partial(), spec.output.fps);
  recorder.frame(simulation->model(), simulation->state().position, simulation->state().time);
  RunCheckpoint run;
  run.writer.frames = 1;
  run.command_line = options.info.command_line;
  run.options = render_flags_json(options.render);
  run.scene = scene_to_json(spec).dump();
  const RunStatus status = simulate_frames(spec, observer, *simulation, writer, recorder, run, wall);

  // 3. The folder finished.
  RunResult result =
      finish_run(spec, *render_plan, std::move(simulation), writer, recorder, status, wall.seconds(), options.report);
  if (status == RunStatus::completed || status == RunStatus::at_rest) remove_leftovers(leftovers, observer);
  return result;
}

RunResult resume_run(const std::string& path, const RunOptions& options) {
  RunObserver silent;
  RunObserver& observer = options.observer != nullptr ? *options.observer : silent;
  // 1. Input: the run, its scene and checkpoint, the output folder. As for a new run, every
  //    refusal comes before anything on disk changes.
  const ResumeTarget target = find_resume_target(path);
  const SceneSpec spec = load_scene_file((target.folder / RunWriter::kSceneFile).string());
  const MemoryAllowance memory = check_run_memory(spec, *parse_render_flags(options.render), options, observer);
  check_export_sizes(spec);
  check_backend_fits(spec);
  check_report_available(options);
  const Stopwatch wall;
  std::unique_ptr<Simulation> simulation = make_unique_simulation(spec, memory);
  RunCheckpoint run;
  std::filesystem::path used;
  try {
    used = load_run_checkpoint(target.checkpoints, *simulation, run, [&observer](const std::string& reason) {
      observer.warning("warning: skipping a damaged checkpoint: " + reason);
    });
  } catch (const CheckpointError& error) {
    throw InputError("--resume", "", error.what());
  }
  // The simulation's arrays fit; the scene must be the one the checkpoint was written for too.
  if (run.scene != scene_to_json(spec).dump()) {
    throw InputError(
        "--resume", "",
        used.string() + " was written for another scene than " + (target.folder / RunWriter::kSceneFile).string());
  }
  const RenderFlags stored = render_flags_from_json(run.options);
  const std::shared_ptr<const RenderPlan> render_plan =
      parse_render_flags(options.resumed_render ? options.resumed_render(stored) : stored);
  RunWriter writer(target.out, RunInfo{options.info.version, run.command_line}, "--resume");
  RunRecorder recorder(render_plan, simulation->model());
  const int fps = spec.output.fps;
  char resuming[64];
  std::snprintf(resuming, sizeof resuming, "%.4g", simulation->state().time);
  observer.notice("resuming " + target.folder.string() + " from " + used.string() + ": t = " + resuming + " s, frame " +
                  std::to_string(run.writer.frames - 1) + " of " + std::to_string(last_frame(spec.output)));

  // 2. The run, from the frame after the checkpoint's. The pictures are made again up to there,
  //    from the frames on disk (the video is one stream).
  writer.resume(target.folder, spec, *simulation, run.writer, options.info.command_line);
  discard_unfinished_checkpoints(writer.partial());
  recorder.begin(writer.partial(), fps);
  if (recorder.active()) {
    std::vector<Vec3> position(simulation->model().particle_count());
    const std::string positions = (writer.partial() / RunWriter::kPositionsFile).string();
    for (std::uint64_t frame = 0; frame < run.writer.frames; ++frame) {
      read_npy_frame(positions, frame, position);
      recorder.frame(simulation->model(), position, frame_time(frame, fps));
    }
  }
  const double wall_before = run.wall_seconds;
  const RunStatus status = simulate_frames(spec, observer, *simulation, writer, recorder, run, wall);

  // 3. The folder finished.
  RunResult result = finish_run(spec, *render_plan, std::move(simulation), writer, recorder, status,
                                wall_before + wall.seconds(), options.report);
  result.resumed_from = used;
  return result;
}

}  // namespace clothsim
