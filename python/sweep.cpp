// clothsim.sweep() (docs/batch.md): the command's sweep from Python. The same plan as `clothsim
// sweep` (run/sweep_plan.h: the grid, the run folders, sweep.json, index.csv, what is done), each
// run one task: called in this process one after the other, or sent to the workers of a Dask
// cluster through `client`. A task is a clothsim.SweepTask, which pickles as its scene's JSON text
// and the run's assignments, so that a worker on another machine needs the module and the shared
// folder only.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bindings.h"
#include "core/error.h"
#include "run/sweep_plan.h"
#include "scene/scene.h"

namespace clothsim::python {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// One run of a sweep: everything a worker needs to make it, and nothing tied to this process.
struct SweepTask {
  std::string scene;  // the scene, as its scene.json text (scene_to_json)
  std::string out;    // the sweep's folder
  SweepRun run;
  py::dict options;  // what clothsim.run takes besides scene, set and out

  // Makes the run, or goes on with it from its checkpoint where an earlier attempt was cut short;
  // returns its state as index.csv writes it. A failed simulation is the state "failed" (its
  // folder says so); bad input or an unwritable folder is "error", its message in the sweep's log
  // for the run, as the command's sweep keeps a run's output there.
  std::string operator()() const {
    const fs::path folder(out);
    const SweepRunStatus before = read_run_status(folder, run);
    if (before.state == SweepRunState::completed) return std::string(to_string(before.state));
    const py::module_ clothsim = py::module_::import("clothsim");
    try {
      if (!before.resume_from.empty()) {
        py::dict resume_options;
        for (const char* key : {"max_memory", "quiet"}) {
          if (options.contains(key)) resume_options[key] = options[key];
        }
        clothsim.attr("resume")(before.resume_from.string(), **resume_options);
      } else {
        py::dict assignments;
        for (const auto& [key, value] : run.assignments) assignments[py::str(key)] = value;
        const SceneSpec spec = parse_scene(scene, "clothsim.sweep scene");
        clothsim.attr("run")(spec, py::arg("set") = assignments, py::arg("out") = (folder / run.folder).string(),
                             **options);
      }
    } catch (py::error_already_set& error) {
      if (error.matches(PyExc_KeyboardInterrupt)) throw;
      if (!error.matches(clothsim.attr("SimulationError"))) write_log(error.what());
    }
    return std::string(to_string(read_run_status(folder, run).state));
  }

  void write_log(const std::string& message) const {
    const fs::path log = sweep_log_path(out, run);
    std::ofstream file(log, std::ios::app);
    file << "== clothsim.sweep: " << run.folder << "\nclothsim: error: " << message << "\n";
  }
};

py::tuple task_state(const SweepTask& task) {
  py::list assignments;
  for (const auto& [key, value] : task.run.assignments) assignments.append(py::make_tuple(key, value));
  return py::make_tuple(task.scene, task.out, task.run.index, task.run.folder, assignments, task.options);
}

SweepTask task_from_state(const py::tuple& state) {
  if (state.size() != 6) throw std::runtime_error("clothsim.SweepTask: a pickled task has 6 parts");
  SweepTask task;
  task.scene = state[0].cast<std::string>();
  task.out = state[1].cast<std::string>();
  task.run.index = state[2].cast<std::size_t>();
  task.run.folder = state[3].cast<std::string>();
  task.run.assignments = state[4].cast<std::vector<std::pair<std::string, std::string>>>();
  task.options = state[5].cast<py::dict>();
  return task;
}

// The parameters' values as set_scene_field() text, each key's values in the order given.
std::vector<SweepParameter> sweep_parameters(const py::dict& params) {
  if (params.empty()) {
    throw InputError("params", "", "needs at least one scene key and its values (clothsim.parameters() lists them)");
  }
  std::vector<SweepParameter> parameters;
  for (const auto& [key_object, values] : params) {
    SweepParameter parameter;
    parameter.key = py::str(key_object).cast<std::string>();
    if (py::isinstance<py::str>(values) || !py::hasattr(values, "__iter__")) {
      throw InputError("params", parameter.key, "expects a list of values");
    }
    for (py::handle value : values) {
      std::string text = field_text(parameter.key, value);
      for (const std::string& earlier : parameter.values) {
        if (earlier == text) throw InputError("params", parameter.key, "lists the value " + text + " twice");
      }
      parameter.values.push_back(std::move(text));
    }
    parameters.push_back(std::move(parameter));
  }
  return parameters;
}

py::dict sweep(py::handle scene, const py::dict& params, py::handle out, py::handle client, bool retry_failed,
               const py::kwargs& options) {
  for (const char* reserved : {"set", "out", "scene"}) {
    if (options.contains(reserved)) {
      throw InputError(reserved, "", "is not a run option of clothsim.sweep (the sweep sets each run's)");
    }
  }
  // 1. Plan, and check every run's scene.
  const SceneSpec spec = scene_from(scene, py::none());
  const std::vector<SweepParameter> parameters = sweep_parameters(params);
  const std::vector<SweepRun> runs = plan_sweep(parameters, "params");
  check_sweep_scenes(spec, runs, "params");
  if (out.is_none()) throw InputError("out", "", "needs the sweep's folder");
  const fs::path folder = py::module_::import("os").attr("fspath")(out).cast<std::string>();

  // 2. Claim the folder. The record is what every run is made from: the scene and the options.
  const std::string scene_text = scene_to_json(spec).dump();
  const std::string options_text = py::module_::import("json")
                                       .attr("dumps")(options, py::arg("sort_keys") = true,
                                                      py::arg("default") = py::module_::import("builtins").attr("str"))
                                       .cast<std::string>();
  claim_sweep_folder(folder, sweep_record({"clothsim.sweep", scene_text, options_text}, parameters, runs.size()),
                     "out");

  // 3. The runs not done: not completed, not failed before (unless retry_failed), not running in
  // another process.
  py::list tasks;
  for (const SweepRun& run : runs) {
    const SweepRunState state = read_run_status(folder, run).state;
    if (state == SweepRunState::completed || state == SweepRunState::running) continue;
    if (state == SweepRunState::failed && !retry_failed) continue;
    tasks.append(SweepTask{scene_text, folder.string(), run, py::dict(options)});
  }
  write_sweep_index(folder, parameters, runs);

  // 4. Run them, here or on the cluster; the index is rewritten as each one ends.
  if (client.is_none()) {
    for (py::handle task : tasks) {
      task();
      write_sweep_index(folder, parameters, runs);
    }
  } else {
    py::list futures;
    for (py::handle task : tasks) futures.append(client.attr("submit")(task, py::arg("pure") = false));
    const py::object as_completed = py::module_::import("distributed").attr("as_completed");
    for (py::handle future : as_completed(futures)) {
      future.attr("result")();  // a task's own exception (not a failed run) stops the sweep here
      write_sweep_index(folder, parameters, runs);
    }
  }

  // 5. Where the whole grid stands.
  py::dict counts;
  for (const char* state : {"completed", "failed", "error", "interrupted", "running", "pending"}) counts[state] = 0;
  for (const SweepRun& run : runs) {
    const std::string state(to_string(read_run_status(folder, run).state));
    counts[py::str(state)] = counts[py::str(state)].cast<int>() + 1;
  }
  counts["runs"] = runs.size();
  counts["index"] = (folder / "index.csv").string();
  return counts;
}

}  // namespace

void bind_sweep(py::module_& module) {
  py::class_<SweepTask>(module, "SweepTask",
                        "One run of a clothsim.sweep(), as it goes to a Dask worker: calling it makes the run "
                        "(or resumes it from its checkpoint) and returns its state. It pickles as its scene's "
                        "JSON text, folders and assignments.")
      .def("__call__", &SweepTask::operator())
      .def_property_readonly("folder", [](const SweepTask& task) { return task.run.folder; })
      .def(py::pickle(&task_state, &task_from_state))
      .def("__repr__", [](const SweepTask& task) { return "<clothsim.SweepTask " + task.run.folder + ">"; });

  module.def("sweep", &sweep, py::arg("scene"), py::arg("params"), py::kw_only(), py::arg("out") = py::none(),
             py::arg("client") = py::none(), py::arg("retry_failed") = false,
             "Runs `scene` (a Scene or anything load_scene() takes) once for each combination of `params` (a dict "
             "from scene key to a list of values, the first key varying slowest) into out/run-0000, "
             "out/run-0001, ..., as `clothsim sweep` does: the same grid, folders, sweep.json record, index.csv "
             "and resumption (a sweep called again runs what is not complete; failed runs again only with "
             "retry_failed). The other keyword arguments are clothsim.run()'s (render='none', max_memory, "
             "quiet, ...). Without `client` the runs are made here one after the other; with a "
             "dask.distributed.Client each run is one task on its workers, which need the clothsim module and "
             "the folder. Every run's scene is checked before anything is written (SceneError). Returns the "
             "grid's counts by state, with 'runs' and 'index' (the path of index.csv).");
}

}  // namespace clothsim::python
