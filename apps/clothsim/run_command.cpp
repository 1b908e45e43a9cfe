// `clothsim run`: load a scene, apply the flags, check the output folder, then simulate frame by
// frame and stream each frame to the output folder.
//
// Everything that can be wrong with the input is checked before anything is created: the scene,
// every flag (through set_scene_field, so a flag's message matches the scene file's), the
// cross-field rules (validate_scene), the model build and the output folder (RunWriter's
// constructor). Only then does the run start; from there on a failure is a simulation failure
// (exit 1, output kept) or an output error (exit 3), never bad input.
//
// Frame k is the state at time k / fps, k = 0 .. round(duration * fps); Simulation::advance_to
// lands exactly on it. SIGINT sets a flag that the frame loop reads after each frame, so an
// interrupted run still ends with a complete, well-formed folder; a second SIGINT kills the
// process the default way (the partial folder is then left behind, named <out>.partial-<pid>).
#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "core/error.h"
#include "core/timer.h"
#include "forces/forces.h"
#include "integrators/stable_step.h"
#include "io/checkpoint.h"
#include "io/npy.h"
#include "io/run_checkpoints.h"
#include "io/run_writer.h"
#include "memory_check.h"
#include "progress_bar.h"
#include "run_render.h"
#include "run_resume.h"
#include "scene/parameters.h"
#include "scene_options.h"
#include "sim/profile.h"
#include "sim/simulation.h"

namespace clothsim::cli {
namespace {

// With --until-rest and no --duration, the run may go on this long before it gives up waiting.
constexpr double kUntilRestDurationCap = 3600.0;  // s

volatile std::sig_atomic_t g_interrupted = 0;

void on_interrupt(int /*signal*/) {
  g_interrupted = 1;
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the process at once
}

// Catches SIGINT for its lifetime.
class InterruptGuard {
 public:
  InterruptGuard() {
    g_interrupted = 0;
    previous_ = std::signal(SIGINT, on_interrupt);
  }
  ~InterruptGuard() { std::signal(SIGINT, previous_ == SIG_ERR ? SIG_DFL : previous_); }
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
  bool interrupted() const { return g_interrupted != 0; }

 private:
  void (*previous_)(int) = SIG_DFL;
};

struct RunOptions {
  SceneOptions scene;  // SCENE or --paper-args, --set and the field flags (scene_options.h)
  std::string out;
  std::string resume;  // --resume PATH
  bool until_rest = false;
  bool quiet = false;
  bool no_progress = false;
  bool profile = false;
  RenderFlags render;  // --render, --size, --camera, --mesh, --show (run_render.h)
  MemoryFlags memory;  // --max-memory (memory_check.h)

  bool given(std::string_view flag) const { return scene.given(flag); }
};

// The scene with every flag applied and checked. Throws InputError.
SceneSpec make_run_scene(const RunOptions& options) {
  return make_scene(options.scene, [&options](SceneSpec& spec) {
    if (!options.until_rest) return false;
    spec.output.until_rest = true;
    if (!options.given("--duration")) spec.output.duration = std::max(spec.output.duration, kUntilRestDurationCap);
    return true;
  });
}

// out/<scene name>, with characters that do not belong in a folder name replaced.
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

std::string format_energy(double joules) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g J", joules);
  return buffer;
}

void print_summary(const SceneSpec& spec, const Simulation& simulation, const RunWriter& writer, RunStatus status,
                   double wall_seconds) {
  const IntegratorStats& stats = simulation.integrator_stats();
  const IntegratorSettings& integrator = spec.integrator;
  const double simulated = writer.last_time();

  std::printf("scene        %s\n", spec.name.c_str());
  std::printf("lattice      %s\n", describe_lattice(simulation.model()).c_str());
  std::string method(to_string(integrator.kind));
  if (integrator.kind == IntegratorKind::rkf45) {
    method += " (rtol ";
    method += format_number(integrator.relative_tolerance);
    method += ", atol ";
    method += format_number(integrator.absolute_tolerance);
    method += ")";
  } else {
    method += " (step ";
    method += format_number(integrator.time_step);
    method += " s)";
  }
  method += ", ";
  method += count_noun(static_cast<std::uint64_t>(simulation.threads()), "thread", "threads");
  std::printf("integrator   %s\n", method.c_str());
  std::printf("status       %s\n", std::string(to_string(status)).c_str());
  std::printf("time         %s s simulated in %s wall, %.3gx real time\n", format_number_short(simulated).c_str(),
              format_duration(wall_seconds).c_str(), wall_seconds > 0.0 ? simulated / wall_seconds : 0.0);
  std::printf("steps        %llu accepted, %llu rejected", static_cast<unsigned long long>(stats.accepted_steps),
              static_cast<unsigned long long>(stats.rejected_steps));
  if (stats.accepted_steps > 0) {
    std::printf("; step %.3g .. %.3g s", stats.smallest_step, stats.largest_step);
  }
  std::printf("; %llu force evaluations", static_cast<unsigned long long>(stats.force_evaluations));
  if (integrator.kind == IntegratorKind::implicit_euler && stats.accepted_steps > 0) {
    std::printf("; CG iterations %.3g per step (most %llu, %llu solves at the cap)",
                static_cast<double>(stats.linear_iterations) / static_cast<double>(stats.accepted_steps),
                static_cast<unsigned long long>(stats.max_linear_iterations),
                static_cast<unsigned long long>(stats.unconverged_solves));
  }
  std::printf("\n");
  const EnergyBalance& initial = writer.initial_energy();
  const EnergyBalance& final = writer.last_energy();
  std::printf("energy       initial %s, final %s (kinetic %s); balance error %s\n",
              format_energy(initial.energy.total()).c_str(), format_energy(final.energy.total()).c_str(),
              format_energy(final.energy.kinetic).c_str(), format_energy(final.error()).c_str());
  std::printf("output       %s/: %zu frames in %.*s and %.*s [%zu, %zu, 3]; %.*s, %.*s, %.*s, %.*s\n",
              writer.out().c_str(), writer.frames(), static_cast<int>(RunWriter::kPositionsFile.size()),
              RunWriter::kPositionsFile.data(), static_cast<int>(RunWriter::kVelocitiesFile.size()),
              RunWriter::kVelocitiesFile.data(), writer.frames(), simulation.model().particle_count(),
              static_cast<int>(RunWriter::kEnergyFile.size()), RunWriter::kEnergyFile.data(),
              static_cast<int>(RunWriter::kSummaryFile.size()), RunWriter::kSummaryFile.data(),
              static_cast<int>(RunWriter::kFinalMeshFile.size()), RunWriter::kFinalMeshFile.data(),
              static_cast<int>(RunWriter::kSceneFile.size()), RunWriter::kSceneFile.data());
  for (ExportFormat format : spec.output.exports) {
    if (format == ExportFormat::pc2) {
      std::printf("export       pc2: %.*s (%zu samples of %zu points) and %.*s\n",
                  static_cast<int>(RunExports::kPointCacheFile.size()), RunExports::kPointCacheFile.data(),
                  writer.frames(), simulation.model().particle_count(),
                  static_cast<int>(RunExports::kRestMeshFile.size()), RunExports::kRestMeshFile.data());
    } else if (format == ExportFormat::obj_sequence) {
      std::printf("export       obj-sequence: %zu files, %s to %s\n", writer.frames(),
                  RunExports::frame_file_name(0).c_str(),
                  RunExports::frame_file_name(writer.frames() > 0 ? writer.frames() - 1 : 0).c_str());
    } else if (format == ExportFormat::gltf && writer.frames() > 0) {
      std::printf("export       gltf: %.*s (frame %zu)\n", static_cast<int>(RunExports::kGlbFile.size()),
                  RunExports::kGlbFile.data(), writer.frames() - 1);
    }
  }
  std::fflush(stdout);
}

// Warns when a fixed-step explicit method's step exceeds the stable step estimated from the
// stiffest springs (integrators/stable_step.h).
void warn_about_stability(const ClothModel& model, const IntegratorSettings& integrator) {
  const StableStep stable = estimate_stable_step(model, integrator.kind);
  if (!(integrator.time_step > stable.step)) return;
  std::ostringstream estimate;
  estimate << std::setprecision(3) << stable.step;
  std::cerr << "clothsim: warning: integrator.time_step = " << format_number(integrator.time_step) << " s is above "
            << to_string(integrator.kind) << "'s estimated stable step, " << estimate.str()
            << " s (the stiffest springs are at " << model.describe_particle(stable.particle)
            << "); the run may blow up. A smaller --time-step, or --integrator rkf45 or implicit-euler, avoids it.\n";
}

// The frame loop's checkpoints (io/run_checkpoints.h): after the first frame at least
// output.checkpoint_every after the previous one (or the run's start), and after the last frame of
// an interrupted run, so that it resumes where it stopped.
class Checkpointer {
 public:
  Checkpointer(const SceneSpec& spec, RunCheckpoint& run, const Stopwatch& wall)
      : every_(spec.output.checkpoint_every), run_(run), wall_(wall), wall_before_(run.wall_seconds) {
    // A resumed run's last checkpoint was at its first frame's predecessor.
    last_time_ = static_cast<double>(run.writer.frames > 0 ? run.writer.frames - 1 : 0) / spec.output.fps;
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
RunStatus simulate_frames(const SceneSpec& spec, const RunOptions& options, Simulation& simulation, RunWriter& writer,
                          RunRecorder& recorder, RunCheckpoint& run, const Stopwatch& wall) {
  const InterruptGuard interrupt;
  Checkpointer checkpointer(spec, run, wall);
  const int fps = spec.output.fps;
  const auto last_frame = static_cast<std::uint64_t>(std::llround(spec.output.duration * fps));
  ProgressBar progress(!options.quiet && !options.no_progress, static_cast<double>(last_frame) / fps);
  RunStatus status = RunStatus::completed;
  // --until-rest: frames in a row whose kinetic energy is below the threshold, and how many make
  // rest_duration (the first such frame and the one rest_duration later, and all between).
  const auto rest_frames = static_cast<std::uint64_t>(std::llround(spec.output.rest_duration * fps)) + 1;
  for (std::uint64_t frame = run.writer.frames; frame <= last_frame; ++frame) {
    if (interrupt.interrupted()) {
      status = RunStatus::interrupted;
      break;
    }
    if (!simulation.advance_to(static_cast<double>(frame) / fps)) {
      status = RunStatus::failed;
      break;
    }
    writer.write_frame(simulation);
    recorder.frame(simulation.model(), simulation.state().position, simulation.state().time);
    progress.update(simulation.state().time, simulation.integrator_stats().accepted_steps);
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
  progress.clear();
  return status;
}

// The end of a run, new or resumed: the pictures and the folder finished, the summary printed;
// returns the exit code.
int finish_run(const SceneSpec& spec, const RunOptions& options, const RenderPlan& render_plan, Simulation& simulation,
               RunWriter& writer, RunRecorder& recorder, RunStatus status, double wall_seconds) {
  recorder.finish(writer);
  writer.finish(simulation, status, wall_seconds);

  if (!options.quiet) {
    print_summary(spec, simulation, writer, status, wall_seconds);
    if (recorder.active()) {
      std::printf("pictures     %s: %ld frames in %s (%.3g ms per frame); %s\n",
                  describe_render_outputs(render_plan).c_str(), recorder.frames(),
                  format_duration(recorder.seconds()).c_str(),
                  recorder.frames() > 0 ? 1e3 * recorder.seconds() / static_cast<double>(recorder.frames()) : 0.0,
                  recorder.description().c_str());
      std::fflush(stdout);
    }
  }
  if (options.profile) {
    // "output" is everything written during the run: the data files and the pictures.
    std::printf("\nprofile (wall time per phase)\n%s",
                format_profile(profile_rows(simulation, writer.output_seconds() + recorder.seconds(), wall_seconds),
                               simulation.integrator_stats().force_evaluations)
                    .c_str());
    std::fflush(stdout);
  }
  if (status == RunStatus::failed) {
    std::string message = "simulation failed ";
    message += simulation.failure() ? simulation.failure()->message : std::string("without a diagnosis");
    print_error(message);
    std::fprintf(stderr, "clothsim: the %zu frames up to t = %s s are kept in %s (status \"failed\")\n",
                 writer.frames(), format_number_short(writer.last_time()).c_str(), writer.out().c_str());
    return kExitSimulationFailed;
  }
  if (status == RunStatus::interrupted) {
    std::fprintf(stderr, "clothsim: interrupted at t = %s s; %zu frames kept in %s (status \"interrupted\")%s\n",
                 format_number_short(writer.last_time()).c_str(), writer.frames(), writer.out().c_str(),
                 spec.output.checkpoint_every > 0.0
                     ? ("; continue it with: clothsim run --resume " + writer.out().string()).c_str()
                     : "");
    return kExitInterrupted;
  }
  return kExitSuccess;
}

// The picture flags as a checkpoint keeps them (RunCheckpoint::options), and back.
std::string render_flags_json(const RenderFlags& flags) {
  return nlohmann::json{{"render", flags.render}, {"size", flags.size}, {"camera", flags.camera},
                        {"mesh", flags.mesh},     {"show", flags.show}, {"samples", flags.samples}}
      .dump();
}

// The stored flags, each replaced by the one given on the resuming command, if any.
RenderFlags resumed_render_flags(const std::string& stored, const RunOptions& options) {
  RenderFlags flags;
  const nlohmann::json json = nlohmann::json::parse(stored, nullptr, /*allow_exceptions=*/false);
  const auto take = [&](std::string& field, const char* key, std::string_view flag, const std::string& given) {
    if (options.given(flag)) {
      field = given;
    } else if (json.is_object() && json.contains(key) && json[key].is_string()) {
      field = json[key].get<std::string>();
    }
  };
  take(flags.render, "render", "--render", options.render.render);
  take(flags.size, "size", "--size", options.render.size);
  take(flags.camera, "camera", "--camera", options.render.camera);
  take(flags.mesh, "mesh", "--mesh", options.render.mesh);
  take(flags.show, "show", "--show", options.render.show);
  take(flags.samples, "samples", "--samples", options.render.samples);
  return flags;
}

// Item 4 of the run's order: the partial folders earlier runs into the same folder left when they
// died, reported at the start; a run that completes replaces them.
void report_leftovers(const std::vector<LeftoverRun>& leftovers, const RunOptions& options) {
  if (options.quiet) return;
  for (const LeftoverRun& leftover : leftovers) {
    std::fprintf(stderr, "clothsim: note: an earlier run (process %ld) died and left %s; ",
                 static_cast<long>(leftover.pid), leftover.folder.c_str());
    if (leftover.has_checkpoint) {
      std::fprintf(stderr, "to continue it instead, stop this run and use: clothsim run --resume %s. ",
                   leftover.folder.c_str());
    }
    std::fprintf(stderr, "It is deleted when this run completes.\n");
  }
}

void remove_leftovers(const std::vector<LeftoverRun>& leftovers, const RunOptions& options) {
  for (const LeftoverRun& leftover : leftovers) {
    std::error_code error;
    std::filesystem::remove_all(leftover.folder, error);
    if (!options.quiet) {
      std::fprintf(stderr, "clothsim: %s %s, left by the run that died\n", error ? "could not delete" : "deleted",
                   leftover.folder.c_str());
    }
  }
}

int run(const RunOptions& options, const Invocation& invocation) {
  // 1. Input: scene, flags, model, output folder. Bad input throws InputError here, before
  //    anything exists on disk.
  const SceneSpec spec = make_run_scene(options);
  check_run_memory(spec, options.render, options.memory);  // a scene too large is refused before its model is built
  ClothModel model = build_model(spec);
  ClothState initial = build_initial_state(model, spec);
  const std::string out = options.given("--out") ? options.out : default_output_folder(spec);
  RunWriter writer(out, RunInfo{CLOTHSIM_VERSION, invocation.command_line});
  const std::shared_ptr<const RenderPlan> render_plan = parse_render_flags(options.render);
  // The OpenGL context and ffmpeg are checked now, before the run: a machine that cannot make
  // pictures fails at once (exit 3, suggesting --render none), not after a long simulation.
  RunRecorder recorder(render_plan, model);

  // A fixed step past the explicit methods' stability: warned, not refused (the estimate is a bound).
  if (!options.quiet) warn_about_stability(model, spec.integrator);
  const std::vector<LeftoverRun> leftovers = find_leftover_runs(writer.out());
  report_leftovers(leftovers, options);

  // 2. The run.
  SimulationSettings settings;
  settings.integrator = spec.integrator;
  settings.threads = spec.threads;
  const Stopwatch wall;
  Simulation simulation(std::move(model), std::move(initial), settings);
  writer.begin(spec, simulation);
  writer.write_frame(simulation);
  // Pictures go into the partial folder too, so they appear (or not) with everything else.
  recorder.begin(writer.partial(), spec.output.fps);
  recorder.frame(simulation.model(), simulation.state().position, simulation.state().time);
  RunCheckpoint run;
  run.writer.frames = 1;
  run.command_line = invocation.command_line;
  run.options = render_flags_json(options.render);
  run.scene = scene_to_json(spec).dump();
  const RunStatus status = simulate_frames(spec, options, simulation, writer, recorder, run, wall);

  // 3. Report.
  const int exit_code = finish_run(spec, options, *render_plan, simulation, writer, recorder, status, wall.seconds());
  if (status == RunStatus::completed || status == RunStatus::at_rest) remove_leftovers(leftovers, options);
  return exit_code;
}

// --resume PATH: the run PATH names (run_resume.h) goes on from its newest good checkpoint.
int resume(const RunOptions& options, const Invocation& invocation) {
  // 1. Input: the run, its scene and checkpoint, the output folder. As for a new run, every
  //    refusal comes before anything on disk changes.
  const auto given = [&options](std::string_view flag) {
    return options.scene.app->get_option_no_throw(std::string(flag)) != nullptr && options.given(flag);
  };
  for (std::string_view flag : {"SCENE", "--paper-args", "--set", "--material", "--out", "--until-rest"}) {
    if (given(flag)) {
      throw InputError("--resume", "",
                       std::string("cannot be combined with ") + std::string(flag) +
                           ": a resumed run goes on with the scene and output folder it began with");
    }
  }
  for (const FieldFlag& flag : kFieldFlags) {
    if (given(flag.flag)) {
      throw InputError("--resume", "",
                       "cannot be combined with " + std::string(flag.flag) +
                           ": a resumed run goes on with the scene it began with (its scene.json)");
    }
  }
  const ResumeTarget target = find_resume_target(options.resume);
  const SceneSpec spec = load_scene_file((target.folder / RunWriter::kSceneFile).string());
  check_run_memory(spec, options.render, options.memory);
  ClothModel model = build_model(spec);
  ClothState initial = build_initial_state(model, spec);
  SimulationSettings settings;
  settings.integrator = spec.integrator;
  settings.threads = spec.threads;
  const Stopwatch wall;
  Simulation simulation(std::move(model), std::move(initial), settings);
  RunCheckpoint run;
  std::filesystem::path used;
  try {
    used = load_run_checkpoint(target.checkpoints, simulation, run, [](const std::string& reason) {
      std::fprintf(stderr, "clothsim: warning: skipping a damaged checkpoint: %s\n", reason.c_str());
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
  const std::shared_ptr<const RenderPlan> render_plan = parse_render_flags(resumed_render_flags(run.options, options));
  RunWriter writer(target.out, RunInfo{CLOTHSIM_VERSION, run.command_line}, "--resume");
  RunRecorder recorder(render_plan, simulation.model());
  const int fps = spec.output.fps;
  const auto last_frame = static_cast<std::uint64_t>(std::llround(spec.output.duration * fps));
  if (!options.quiet) {
    std::fprintf(stderr, "clothsim: resuming %s from %s: t = %s s, frame %llu of %llu\n", target.folder.c_str(),
                 used.c_str(), format_number_short(simulation.state().time).c_str(),
                 static_cast<unsigned long long>(run.writer.frames - 1), static_cast<unsigned long long>(last_frame));
  }

  // 2. The run, from the frame after the checkpoint's. The pictures are made again up to there,
  //    from the frames on disk (the video is one stream).
  writer.resume(target.folder, spec, simulation, run.writer, invocation.command_line);
  discard_unfinished_checkpoints(writer.partial());
  recorder.begin(writer.partial(), fps);
  if (recorder.active()) {
    std::vector<Vec3> position(simulation.model().particle_count());
    const std::string positions = (writer.partial() / RunWriter::kPositionsFile).string();
    for (std::uint64_t frame = 0; frame < run.writer.frames; ++frame) {
      read_npy_frame(positions, frame, position);
      recorder.frame(simulation.model(), position, static_cast<double>(frame) / fps);
    }
  }
  const double wall_before = run.wall_seconds;
  const RunStatus status = simulate_frames(spec, options, simulation, writer, recorder, run, wall);

  // 3. Report.
  return finish_run(spec, options, *render_plan, simulation, writer, recorder, status, wall_before + wall.seconds());
}

std::string run_footer() {
  std::string text = wrap_text(
      "Flags override the scene's values. --set KEY=VALUE sets any scene parameter ('clothsim params' lists "
      "them); the --set values apply first, in order, then the named flags. Every value is checked before "
      "anything is written.",
      100, 0);
  text += "\n\n";
  text += wrap_text(
      "The output folder (default out/<scene name>) holds positions.npy and velocities.npy (float64 [frames, "
      "particles, 3]; frame k at t = k/fps, frame 0 the initial state), energy.csv, summary.json, final.obj "
      "(split along any tears), scene.json (run it to reproduce the run), connectors.npy and "
      "connector_break_time.npy (each connector's particles and when it broke), and unless --render none, "
      "final.png (the last frame) and "
      "animation.mp4 (H.264, one video frame per output frame, at --fps); with --export pc2, animation.pc2 and "
      "rest.obj (a point cache of every frame, for Blender's Mesh Cache modifier), with --export obj-sequence, "
      "frames/frame_000000.obj and on, with --export gltf, final.glb (the last frame as binary glTF) "
      "(docs/exports.md); with --checkpoint-every, checkpoints/ (the "
      "newest two checkpoints). It is written as <out>.partial-<pid> and renamed into place at the end; an "
      "existing <out> is replaced only if a clothsim run wrote it. A run killed or interrupted after a "
      "checkpoint continues with --resume, bit for bit as if it had not stopped (docs/cli.md).",
      100, 0);
  text +=
      "\n\n"
      "Examples:\n"
      "  clothsim run paper-fig4\n"
      "  clothsim run --paper-args 21,21,1,4,1,1400,200,80,5,1 --duration 10 --out out/fig4\n"
      "  clothsim run my-scene.json --integrator rk4 --time-step 1e-3 --fps 30\n"
      "  clothsim run paper-fig5 --until-rest --rest-energy 1e-4\n"
      "  clothsim run paper-fig5 --set springs.adjacent.stiffness=400 --set environment.air_drag=0.1\n"
      "  clothsim run out/paper-fig4/scene.json --out out/paper-fig4-again   # reproduce a run\n"
      "  clothsim run paper-fig5 --size 1920x1080 --camera 0,10 --show wireframe\n"
      "  clothsim run drape-corners --render none   # data only, no OpenGL\n"
      "  clothsim run paper-fig5 --export pc2,obj-sequence   # for Blender and other tools\n"
      "  clothsim run cotton-drape --checkpoint-every 0.5   # then, if it is killed:\n"
      "  clothsim run --resume out/cotton-drape.partial-4711\n"
      "\n";
  text += exit_code_help();
  return text;
}

}  // namespace

Subcommand add_run_command(CLI::App& parent, const Invocation& invocation) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* app = parent.add_subcommand("run", "Simulate a scene and write its output folder");
  add_scene_options(*app, options->scene);
  app->add_flag("--until-rest", options->until_rest,
                "stop once the kinetic energy has stayed below --rest-energy at every frame for "
                "output.rest_duration (default 1 s); without --duration, run at most max(scene duration, 3600 s)");
  app->add_option("--resume", options->resume,
                  "continue a run from its newest checkpoint: PATH is its output folder (interrupted), the partial "
                  "folder <out>.partial-<pid> a killed run left, or a checkpoint file in either; no scene or scene "
                  "flags with it")
      ->type_name("PATH");
  app->add_option("--out", options->out, "output folder (default out/<scene name>)")
      ->type_name("DIR")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app->add_flag("--quiet", options->quiet, "print nothing but errors");
  app->add_flag("--no-progress", options->no_progress, "no progress bar (it is shown only on a terminal anyway)");
  app->add_flag("--profile", options->profile,
                "print where the wall time went: forces, integration (stage sums, error control), checks, output");
  add_render_flags(*app, options->render);
  add_memory_flag(*app, options->memory);
  app->footer(run_footer());
  return {app, [options, invocation] {
            return options->given("--resume") ? resume(*options, invocation) : run(*options, invocation);
          }};
}

}  // namespace clothsim::cli
