// `clothsim run`: load a scene, apply the flags, and run it into its output folder through the
// library's run driver (run/run_scene.h), which the Python module's clothsim.run() shares; this
// file is the command's shell around it: the flags, the memory check, the progress bar, Ctrl-C,
// the summary printed at the end and the exit code.
//
// Everything that can be wrong with the input is checked before anything is created: the scene,
// every flag (through set_scene_field, so a flag's message matches the scene file's), the
// cross-field rules (validate_scene), the picture flags, the memory, the model build and the
// output folder (the driver's first step). Only then does the run start; from there on a failure
// is a simulation failure (exit 1, output kept) or an output error (exit 3), never bad input.
//
// SIGINT sets a flag that the driver polls before each frame, so an interrupted run still ends
// with a complete, well-formed folder; a second SIGINT kills the process the default way (the
// partial folder is then left behind, named <out>.partial-<pid>).
#include <algorithm>
#include <csignal>
#include <cstdio>
#include <optional>
#include <string>

#include "commands.h"
#include "core/error.h"
#include "memory_check.h"
#include "progress_bar.h"
#include "run/run_scene.h"
#include "run/run_writer.h"
#include "run_render.h"
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

// The command's flags; run_options() turns them into the library's RunOptions (run/run_scene.h).
struct RunFlags {
  SceneOptions scene;  // SCENE or --paper-args, --set and the field flags (scene_options.h)
  std::string out;
  std::string resume;  // --resume PATH
  bool until_rest = false;
  bool quiet = false;
  bool no_progress = false;
  bool profile = false;
  bool report = false;  // --report: the run's report.html at the end (run/run_report.h)
  RenderFlags render;   // --render, --size, --camera, --mesh, --show (run_render.h)
  MemoryFlags memory;   // --max-memory (memory_check.h)

  bool given(std::string_view flag) const { return scene.given(flag); }
};

// The scene with every flag applied and checked. Throws InputError.
SceneSpec make_run_scene(const RunFlags& options) {
  return make_scene(options.scene, [&options](SceneSpec& spec) {
    if (!options.until_rest) return false;
    spec.output.until_rest = true;
    if (!options.given("--duration")) spec.output.duration = std::max(spec.output.duration, kUntilRestDurationCap);
    return true;
  });
}

std::string format_energy(double joules) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g J", joules);
  return buffer;
}

void print_summary(const RunResult& result) {
  const SceneSpec& spec = result.scene;
  const Simulation& simulation = *result.simulation;
  const RunStatus status = result.status;
  const double wall_seconds = result.wall_seconds;
  const IntegratorStats& stats = simulation.integrator_stats();
  const IntegratorSettings& integrator = simulation.settings().integrator;
  const double simulated = result.last_time;

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
  if ((integrator.kind == IntegratorKind::implicit_euler || integrator.kind == IntegratorKind::imex) &&
      stats.accepted_steps > 0) {
    std::printf("; CG iterations %.3g per step (most %llu, %llu solves at the cap)",
                static_cast<double>(stats.cg_iterations) / static_cast<double>(stats.accepted_steps),
                static_cast<unsigned long long>(stats.cg_max_iterations_in_a_step),
                static_cast<unsigned long long>(stats.cg_unconverged_solves));
  }
  std::printf("\n");
  const EnergyBalance& initial = result.initial_energy;
  const EnergyBalance& final = result.last_energy;
  std::printf("energy       initial %s, final %s (kinetic %s); balance error %s\n",
              format_energy(initial.energy.total()).c_str(), format_energy(final.energy.total()).c_str(),
              format_energy(final.energy.kinetic).c_str(), format_energy(final.error()).c_str());
  std::printf("output       %s/: %zu frames in %.*s and %.*s [%zu, %zu, 3]; %.*s, %.*s, %.*s, %.*s\n",
              result.out.c_str(), result.frames, static_cast<int>(RunWriter::kPositionsFile.size()),
              RunWriter::kPositionsFile.data(), static_cast<int>(RunWriter::kVelocitiesFile.size()),
              RunWriter::kVelocitiesFile.data(), result.frames, simulation.model().particle_count(),
              static_cast<int>(RunWriter::kEnergyFile.size()), RunWriter::kEnergyFile.data(),
              static_cast<int>(RunWriter::kSummaryFile.size()), RunWriter::kSummaryFile.data(),
              static_cast<int>(RunWriter::kFinalMeshFile.size()), RunWriter::kFinalMeshFile.data(),
              static_cast<int>(RunWriter::kSceneFile.size()), RunWriter::kSceneFile.data());
  for (ExportFormat format : spec.output.exports) {
    if (format == ExportFormat::pc2) {
      std::printf("export       pc2: %.*s (%zu samples of %zu points) and %.*s\n",
                  static_cast<int>(RunExports::kPointCacheFile.size()), RunExports::kPointCacheFile.data(),
                  result.frames, simulation.model().particle_count(),
                  static_cast<int>(RunExports::kRestMeshFile.size()), RunExports::kRestMeshFile.data());
    } else if (format == ExportFormat::obj_sequence) {
      std::printf("export       obj-sequence: %zu files, %s to %s\n", result.frames,
                  RunExports::frame_file_name(0).c_str(),
                  RunExports::frame_file_name(result.frames > 0 ? result.frames - 1 : 0).c_str());
    } else if (format == ExportFormat::gltf && result.frames > 0) {
      std::printf("export       gltf: %.*s (frame %zu)\n", static_cast<int>(RunExports::kGlbFile.size()),
                  RunExports::kGlbFile.data(), result.frames - 1);
    } else if (format == ExportFormat::gltf_animation && result.frames > 0) {
      std::printf("export       gltf-animation: %.*s (%zu frames as morph targets, %d fps)\n",
                  static_cast<int>(RunExports::kAnimationGlbFile.size()), RunExports::kAnimationGlbFile.data(),
                  result.frames, spec.output.fps);
    }
  }
  std::fflush(stdout);
}

// What the command shows of a run while it goes on: the progress bar (unless --quiet or
// --no-progress), notices (unless --quiet) and warnings on stderr, and Ctrl-C,
// caught while the frames are simulated.
class CommandObserver final : public RunObserver {
 public:
  explicit CommandObserver(const RunFlags& options) : options_(options) {}

  void notice(const std::string& message) override {
    if (!options_.quiet) warning(message);
  }
  void warning(const std::string& message) override { std::fprintf(stderr, "clothsim: %s\n", message.c_str()); }
  // The library refused a scene above the limit; what passed may still grow past it.
  void memory_checked(const MemoryLimit& limit) override { cap_run_growth(limit); }
  void frames_begin(double end_time) override {
    interrupt_.emplace();
    progress_.emplace(!options_.quiet && !options_.no_progress, end_time);
  }
  void frame_done(double time, std::uint64_t accepted_steps) override {
    if (progress_) progress_->update(time, accepted_steps);
  }
  void frames_end() override {
    progress_.reset();  // erases the line
    interrupt_.reset();
  }
  bool interrupted() override { return interrupt_ && interrupt_->interrupted(); }

 private:
  const RunFlags& options_;
  std::optional<InterruptGuard> interrupt_;
  std::optional<ProgressBar> progress_;
};

// The library's options for a run from the command's.
RunOptions run_options(const RunFlags& options, const Invocation& invocation, RunObserver& observer) {
  RunOptions run;
  if (options.given("--out")) run.out = options.out;
  run.info = RunInfo{CLOTHSIM_VERSION, invocation.command_line};
  run.render = options.render;
  run.observer = &observer;
  run.max_memory = max_memory(options.memory);
  run.report = options.report;
  // A resumed run keeps the picture flags it began with, but for those given again.
  run.resumed_render = [&options](const RenderFlags& stored) {
    RenderFlags flags = stored;
    const auto take = [&options](std::string& field, std::string_view flag, const std::string& given) {
      if (options.given(flag)) field = given;
    };
    take(flags.render, "--render", options.render.render);
    take(flags.size, "--size", options.render.size);
    take(flags.camera, "--camera", options.render.camera);
    take(flags.mesh, "--mesh", options.render.mesh);
    take(flags.show, "--show", options.render.show);
    take(flags.samples, "--samples", options.render.samples);
    return flags;
  };
  return run;
}

// The end of a run, new or resumed: the summary printed; returns the exit code.
int report_run(const RunResult& result, const RunFlags& options) {
  const Simulation& simulation = *result.simulation;
  if (!options.quiet) {
    print_summary(result);
    if (!result.report.empty()) std::printf("report       %s\n", result.report.string().c_str());
    if (result.pictures) {
      std::printf(
          "pictures     %s: %ld frames in %s (%.3g ms per frame); %s\n", result.picture_files.c_str(),
          result.picture_frames, format_duration(result.picture_seconds).c_str(),
          result.picture_frames > 0 ? 1e3 * result.picture_seconds / static_cast<double>(result.picture_frames) : 0.0,
          result.picture_description.c_str());
      std::fflush(stdout);
    }
  }
  if (options.profile) {
    // "output" is everything written during the run: the data files and the pictures.
    std::printf(
        "\nprofile (wall time per stage)\n%s",
        format_profile(profile_rows(simulation, result.output_seconds + result.picture_seconds, result.wall_seconds),
                       simulation.integrator_stats().force_evaluations)
            .c_str());
    std::fputs(simulation.profile_notes().c_str(), stdout);
    std::fflush(stdout);
  }
  if (result.status == RunStatus::failed) {
    std::string message = "simulation failed ";
    message += simulation.failure() ? simulation.failure()->message : std::string("without a diagnosis");
    print_error(message);
    std::fprintf(stderr, "clothsim: the %zu frames up to t = %s s are kept in %s (status \"failed\")\n", result.frames,
                 format_number_short(result.last_time).c_str(), result.out.c_str());
    return kExitSimulationFailed;
  }
  if (result.status == RunStatus::interrupted) {
    std::fprintf(stderr, "clothsim: interrupted at t = %s s; %zu frames kept in %s (status \"interrupted\")%s\n",
                 format_number_short(result.last_time).c_str(), result.frames, result.out.c_str(),
                 result.scene.output.checkpoint_every > 0.0
                     ? ("; continue it with: clothsim run --resume " + result.out.string()).c_str()
                     : "");
    return kExitInterrupted;
  }
  return kExitSuccess;
}

int run(const RunFlags& options, const Invocation& invocation) {
  const SceneSpec spec = make_run_scene(options);
  CommandObserver observer(options);
  return report_run(run_scene(spec, run_options(options, invocation, observer)), options);
}

// --resume PATH: the run PATH names (run/run_folders.h) goes on from its newest good checkpoint.
int resume(const RunFlags& options, const Invocation& invocation) {
  // A resumed run goes on with its scene and output folder: refused before anything changes.
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
  CommandObserver observer(options);
  return report_run(resume_run(options.resume, run_options(options, invocation, observer)), options);
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
      "frames/frame_000000.obj and on, with --export gltf, final.glb (the last frame as binary glTF), with --export "
      "gltf-animation, animation.glb (every frame in one binary glTF, played at --fps) "
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
  auto options = std::make_shared<RunFlags>();
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
                "print where the wall time went, by the stages of the step: forces, integration (and its parts: stage "
                "sums, solution and error, ...), collisions, anchors, events, checks; then output, other, total");
  app->add_flag("--report", options->report,
                "write report.html in the output folder at the end: the run in a browser, a 3D player, plots over "
                "time and the summary, in one file (as 'clothsim report OUT' does; docs/report.md)");
  add_render_flags(*app, options->render);
  add_memory_flag(*app, options->memory);
  app->footer(run_footer());
  return {app, [options, invocation] {
            return options->given("--resume") ? resume(*options, invocation) : run(*options, invocation);
          }};
}

}  // namespace clothsim::cli
