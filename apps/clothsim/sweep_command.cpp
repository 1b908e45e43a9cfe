// `clothsim sweep`: runs a scene over a grid of parameter values, one `clothsim run` per grid
// point, each a child process writing <out>/run-NNNN (docs/batch.md; the plan is sweep_plan.h).
//
// Child processes rather than threads: each run is exactly what `clothsim run` would make, with
// its own summary.json, memory check and failure handling, and a run that dies takes nothing
// else with it. The stages:
//   1. plan      the grid, this shard's runs, and every run's scene built and checked, so that a
//                bad value stops the sweep before anything is written (exit 2);
//   2. claim     the sweep's folder, with its record (sweep.json);
//   3. schedule  the runs not yet done, --jobs at a time; an interrupted run with a checkpoint is
//                resumed (`clothsim run --resume`), the rest started afresh;
//   4. index     index.csv rewritten after every run, from the folders.
// Ctrl-C (or SIGTERM, which a batch system sends at its time limit) is passed to the runs as
// SIGINT: each stops as "interrupted" and the sweep exits 130 once they have; running it again
// goes on where it stopped.
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "commands.h"
#include "core/child_process.h"
#include "core/error.h"
#include "memory_check.h"
#include "run/run_report.h"
#include "run/run_writer.h"
#include "run/sweep_plan.h"
#include "run_render.h"
#include "scene_options.h"

namespace clothsim::cli {
namespace {

namespace fs = std::filesystem;

volatile std::sig_atomic_t g_stop_signal = 0;
void on_stop_signal(int signal) { g_stop_signal = signal; }

// SIGINT and SIGTERM handlers for the sweep's life, installed without SA_RESTART so that a signal
// wakes the wait for the runs.
class StopSignals {
 public:
  StopSignals() {
    g_stop_signal = 0;
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &previous_int_);
    sigaction(SIGTERM, &action, &previous_term_);
  }
  ~StopSignals() {
    sigaction(SIGINT, &previous_int_, nullptr);
    sigaction(SIGTERM, &previous_term_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  bool stopped() const { return g_stop_signal != 0; }

 private:
  struct sigaction previous_int_ {};
  struct sigaction previous_term_ {};
};

struct SweepOptions {
  SceneOptions scene;  // SCENE or --paper-args, --material, --set and the field flags, passed to every run
  bool until_rest = false;
  RenderFlags render;
  MemoryFlags memory;
  std::vector<std::string> parameters;  // --param KEY=V1,V2,...
  std::string out;
  std::string shard = "1/1";
  int jobs = 1;
  bool retry_failed = false;
  bool quiet = false;
  bool report = false;  // --report: each run's report.html and the index's page
};

// The sweep's own options; every other option given is passed on to each run as written.
bool is_sweep_option(const CLI::Option& option) {
  static const std::vector<std::string> kOwn = {"param",        "out",   "shard",  "jobs",
                                                "retry-failed", "quiet", "report", "help"};
  const std::vector<std::string>& names = option.get_lnames();
  return !names.empty() && std::find(kOwn.begin(), kOwn.end(), names.front()) != kOwn.end();
}

// The run arguments the user gave, in the order CLI11 lists the options (the order of --set
// values is kept: each option keeps its own values in order).
std::vector<std::string> run_arguments(const CLI::App& app) {
  std::vector<std::string> arguments;
  for (const CLI::Option* option : app.get_options()) {
    if (option->count() == 0 || is_sweep_option(*option)) continue;
    if (option->get_positional() && option->get_lnames().empty()) {
      for (const std::string& value : option->results()) arguments.push_back(value);
      continue;
    }
    const std::string name = "--" + option->get_lnames().front();
    if (option->get_type_size_min() == 0) {
      arguments.push_back(name);  // a flag
      continue;
    }
    for (const std::string& value : option->results()) {
      arguments.push_back(name);
      arguments.push_back(value);
    }
  }
  return arguments;
}

// Builds and checks every run's scene: the flags' scene, then the run's --param values.
void check_run_scenes(const SweepOptions& options, const std::vector<SweepParameter>& parameters,
                      const std::vector<SweepRun>& runs) {
  for (const SweepParameter& parameter : parameters) {
    for (const FieldFlag& flag : kFieldFlags) {
      if (flag.key != parameter.key) continue;
      if (options.scene.app->get_option_no_throw(std::string(flag.flag)) && options.scene.given(flag.flag)) {
        throw InputError("--param", parameter.key,
                         "is also given by " + std::string(flag.flag) + ": give it only with --param");
      }
    }
  }
  check_sweep_scenes(make_scene(options.scene), runs, "--param");
}

std::string describe_assignments(const SweepRun& run) {
  std::string text;
  for (const auto& [key, value] : run.assignments) text += (text.empty() ? "" : ", ") + key + "=" + value;
  return text;
}

// What a run's log says went wrong: its last error line, or else its last line.
std::string log_diagnosis(const fs::path& log) {
  std::ifstream in(log);
  std::string line;
  std::string last;
  std::string last_error;
  while (std::getline(in, line)) {
    if (line.empty() || line.starts_with("== ")) continue;
    last = line;
    if (line.starts_with("clothsim: error: ")) last_error = line;
  }
  return last_error.empty() ? last : last_error;
}

class Scheduler {
 public:
  Scheduler(const fs::path& out, std::vector<std::string> base_arguments, const SweepOptions& options,
            const std::vector<SweepParameter>& parameters, const std::vector<SweepRun>& runs)
      : out_(out),
        executable_(fs::read_symlink("/proc/self/exe")),
        base_arguments_(std::move(base_arguments)),
        options_(options),
        parameters_(parameters),
        runs_(runs) {}

  // Runs `todo`, --jobs at a time; returns false when a stop signal cut it short.
  bool run_all(const std::vector<const SweepRun*>& todo, const StopSignals& signals) {
    total_ = todo.size();
    std::size_t next = 0;
    bool forwarded = false;
    while (next < todo.size() || !running_.empty()) {
      while (!signals.stopped() && next < todo.size() && running_.size() < static_cast<std::size_t>(options_.jobs)) {
        start(*todo[next++]);
      }
      if (running_.empty()) break;
      int status = 0;
      const pid_t pid = ::waitpid(-1, &status, 0);
      if (signals.stopped() && !forwarded) {
        for (const auto& [child, started] : running_) ::kill(child, SIGINT);
        forwarded = true;
      }
      if (pid > 0) finish(pid, status);
    }
    return !signals.stopped();
  }

  std::size_t count(SweepRunState state) const { return counts_.count(state) ? counts_.at(state) : 0; }

 private:
  struct Started {
    const SweepRun* run;
    std::chrono::steady_clock::time_point start;
    bool resumed;
  };

  void start(const SweepRun& run) {
    const SweepRunStatus status = read_run_status(out_, run);
    std::vector<std::string> arguments = {executable_.string(), "run"};
    const bool resumed = !status.resume_from.empty();
    if (resumed) {
      arguments.insert(arguments.end(), {"--resume", status.resume_from.string()});
    } else {
      arguments.insert(arguments.end(), base_arguments_.begin(), base_arguments_.end());
      for (const auto& [key, value] : run.assignments) arguments.insert(arguments.end(), {"--set", key + "=" + value});
      arguments.insert(arguments.end(), {"--out", (out_ / run.folder).string()});
    }
    arguments.push_back("--no-progress");

    const fs::path log = sweep_log_path(out_, run);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (fd < 0) throw OutputError(log.string() + ": cannot open the run's log");
    std::string header = "== clothsim sweep, " + timestamp() + ":";
    for (const std::string& argument : arguments) header += " " + argument;
    header += "\n";
    if (::write(fd, header.data(), header.size()) < 0) {
      ::close(fd);
      throw OutputError(log.string() + ": cannot write the run's log");
    }
    try {
      const pid_t pid = spawn_process(arguments, {.output_fd = fd});
      running_[pid] = {&run, std::chrono::steady_clock::now(), resumed};
    } catch (const std::system_error& error) {
      ::close(fd);
      throw OutputError(error.what());
    }
    ::close(fd);
  }

  void finish(pid_t pid, int exit_status) {
    const auto found = running_.find(pid);
    if (found == running_.end()) return;
    const Started started = found->second;
    running_.erase(found);
    const SweepRun& run = *started.run;
    const SweepRunState state = read_run_status(out_, run).state;
    ++counts_[state];
    ++done_;
    write_sweep_index(out_, parameters_, runs_);
    if (options_.quiet && state == SweepRunState::completed) return;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started.start).count();
    std::string line = "[" + std::to_string(done_) + "/" + std::to_string(total_) + "] " + run.folder + " (" +
                       describe_assignments(run) + "): " + std::string(to_string(state)) +
                       (started.resumed ? " (resumed)" : "") + " in " + format_duration(seconds);
    if (state != SweepRunState::completed) {
      line += "; the run " + describe_exit_status(exit_status) + ": " + log_diagnosis(sweep_log_path(out_, run)) +
              " (log: " + sweep_log_path(out_, run).string() + ")";
    }
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
  }

  static std::string timestamp() {
    const std::time_t now = std::time(nullptr);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%d %H:%M:%S", std::localtime(&now));
    return text;
  }

  fs::path out_;
  fs::path executable_;
  std::vector<std::string> base_arguments_;
  const SweepOptions& options_;
  const std::vector<SweepParameter>& parameters_;
  const std::vector<SweepRun>& runs_;
  std::map<pid_t, Started> running_;
  std::map<SweepRunState, std::size_t> counts_;
  std::size_t done_ = 0;
  std::size_t total_ = 0;
};

int sweep(const SweepOptions& options, const CLI::App& app) {
  // 1. Plan.
  if (options.parameters.empty()) {
    throw InputError("sweep", "", "needs at least one --param KEY=V1,V2,... (list the keys with 'clothsim params')");
  }
  std::vector<SweepParameter> parameters;
  for (const std::string& text : options.parameters) parameters.push_back(parse_sweep_parameter(text));
  const std::vector<SweepRun> runs = plan_sweep(parameters);
  const Shard shard = parse_shard(options.shard);
  if (options.jobs < 1 || options.jobs > 1024) {
    throw InputError("--jobs", "", "must be an integer in [1, 1024], got " + std::to_string(options.jobs));
  }
  check_run_scenes(options, parameters, runs);
  std::vector<std::string> arguments = run_arguments(app);

  // 2. Claim the folder. The record holds the arguments every run shares, not --threads, which
  // --jobs adds and which changes no result (docs/performance.md: threads give identical bits).
  const fs::path out = options.out;
  claim_sweep_folder(out, sweep_record(arguments, parameters, runs.size()));
  const bool threads_given =
      options.scene.given("--threads") ||
      std::any_of(options.scene.assignments.begin(), options.scene.assignments.end(),
                  [](const std::string& a) { return a.starts_with("threads="); }) ||
      std::any_of(parameters.begin(), parameters.end(), [](const SweepParameter& p) { return p.key == "threads"; });
  // --report is the sweep's own (a sweep's record does not change with it) and each run's.
  if (options.report) arguments.emplace_back("--report");
  if (options.jobs > 1 && !threads_given) {
    // Runs started together would each see every core idle and take them all.
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    arguments.insert(arguments.end(), {"--threads", std::to_string(std::max(1u, cores / options.jobs))});
  }

  // 3. Schedule this shard's runs that are not done.
  std::vector<const SweepRun*> todo;
  std::size_t done = 0;
  std::size_t elsewhere = 0;
  std::size_t failed_before = 0;
  std::size_t mine = 0;
  for (const SweepRun& run : runs) {
    if (!shard.takes(run.index)) continue;
    ++mine;
    const SweepRunState state = read_run_status(out, run).state;
    if (state == SweepRunState::completed) {
      ++done;
    } else if (state == SweepRunState::failed && !options.retry_failed) {
      ++failed_before;
    } else if (state == SweepRunState::running) {
      ++elsewhere;
    } else {
      todo.push_back(&run);
    }
  }
  if (!options.quiet) {
    std::string line = "sweep: " + count_noun(runs.size(), "run", "runs");
    if (shard.count > 1) line += ", shard " + options.shard + " takes " + std::to_string(mine);
    line += "; " + std::to_string(done) + " already complete";
    if (failed_before > 0)
      line += ", " + std::to_string(failed_before) + " failed before (--retry-failed runs them again)";
    if (elsewhere > 0) line += ", " + std::to_string(elsewhere) + " running in another process";
    line += "; " + std::to_string(todo.size()) + " to run, " + std::to_string(options.jobs) + " at a time";
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
  }
  write_sweep_index(out, parameters, runs);
  Scheduler scheduler(out, arguments, options, parameters, runs);
  const StopSignals signals;
  const bool whole = scheduler.run_all(todo, signals);

  // 4. Index (written after each run), its page, and the outcome.
  write_sweep_index(out, parameters, runs);
  if (options.report) write_sweep_report(out);
  const std::size_t failed = failed_before + scheduler.count(SweepRunState::failed) +
                             scheduler.count(SweepRunState::error) +
                             (whole ? scheduler.count(SweepRunState::interrupted) : 0);
  if (!options.quiet) {
    std::printf("sweep: %zu of %zu runs of this %s complete, %zu failed%s; index: %s\n",
                done + scheduler.count(SweepRunState::completed), mine, shard.count > 1 ? "shard" : "sweep", failed,
                whole ? "" : " (interrupted: run the same command again to go on)",
                (out / "index.csv").string().c_str());
  }
  if (!whole) return kExitInterrupted;
  return failed > 0 ? kExitSimulationFailed : kExitSuccess;
}

std::string sweep_footer() {
  return "Runs SCENE once for each combination of the --param values (the first --param varies slowest), each "
         "as 'clothsim run' with --set KEY=VALUE, into OUT/run-0000, OUT/run-0001, ...; every other option "
         "given is passed to each run. OUT/index.csv lists the runs with their parameters, status, wall time and "
         "final energies; OUT/logs/ holds each run's messages. Running the same command again skips the runs "
         "already complete (and those that failed, unless --retry-failed) and resumes interrupted runs from "
         "their checkpoints (--checkpoint-every).\n\n"
         "Examples:\n"
         "  clothsim sweep paper-fig5 --param springs.connector.stiffness=40,80,160 --param output.fps=30,60 \\\n"
         "      --duration 2 --render none --out out/sweep --jobs 2\n"
         "  clothsim sweep cotton-drape --param environment.gravity=[0,-9.81,0],[0,-1.62,0] --out out/g\n"
         "  clothsim sweep paper-fig5 --param ... --out shared/sweep --shard $SLURM_ARRAY_TASK_ID/8   # 1..8\n\n" +
         exit_code_help() + "\n  (sweep: 1 when any run failed, 130 when interrupted)\n\nDocumentation: docs/batch.md.";
}

}  // namespace

Subcommand add_sweep_command(CLI::App& parent) {
  auto options = std::make_shared<SweepOptions>();
  CLI::App* app = parent.add_subcommand("sweep", "Run a scene over a grid of parameter values, one folder per run");
  app->add_option("--param", options->parameters,
                  "a scene field (any key of --set) and its values, comma-separated; a vector or list in "
                  "brackets: environment.gravity=[0,-9.81,0],[0,-1.62,0] (repeatable: the runs are every combination)")
      ->type_name("KEY=V1,V2,...")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app->add_option("--out", options->out, "the sweep's folder: run-NNNN/ per run, index.csv, logs/, sweep.json")
      ->type_name("DIR")
      ->required();
  app->add_option("--jobs", options->jobs, "runs at once on this machine (default 1)")->type_name("N");
  app->add_option("--shard", options->shard,
                  "run only the K-th of N shares of the grid (runs i with i mod N = K - 1), for job arrays")
      ->type_name("K/N");
  app->add_flag("--retry-failed", options->retry_failed, "run again the runs whose simulation failed before");
  app->add_flag("--quiet", options->quiet, "print only runs that did not complete, and errors");
  app->add_flag("--report", options->report,
                "each run writes its report.html (clothsim run --report), and the sweep report.html: index.csv as a "
                "page with a link to each run's report");
  add_scene_options(*app, options->scene);
  app->add_flag("--until-rest", options->until_rest, "passed to each run (see 'clothsim run --help')");
  add_render_flags(*app, options->render);
  add_memory_flag(*app, options->memory);
  app->footer(sweep_footer());
  return {app, [options, app] { return sweep(*options, *app); }};
}

}  // namespace clothsim::cli
