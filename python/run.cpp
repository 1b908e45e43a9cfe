// clothsim.run() and clothsim.resume() (bindings.h): the library's run driver (run/run_scene.h),
// which `clothsim run` uses too, so the folder is the command's, file for file.
#include <pybind11/pybind11.h>

#include <memory>
#include <string>

#include "bindings.h"
#include "run/run_scene.h"
#include "scene/builtin_scenes.h"
#include "scene/parameters.h"

namespace clothsim::python {
namespace {

// What Python hears of a run: the command's notices and warnings on sys.stderr (notices unless
// quiet), and Ctrl-C. Called from the run's thread while it runs without the GIL.
class PythonObserver final : public RunObserver {
 public:
  explicit PythonObserver(bool quiet) : quiet_(quiet) {}

  void notice(const std::string& message) override {
    if (!quiet_) warning(message);
  }
  void warning(const std::string& message) override {
    const py::gil_scoped_acquire gil;
    py::print("clothsim: " + message, py::arg("file") = py::module_::import("sys").attr("stderr"));
  }
  // KeyboardInterrupt (or any exception a signal handler raises) stops the run after a complete
  // frame; it is raised again once the folder is finished.
  bool interrupted() override {
    if (pending_) return true;
    const py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) pending_ = std::make_unique<py::error_already_set>();
    return pending_ != nullptr;
  }
  // Raises what interrupted the run, if anything did. With the GIL.
  void raise_pending() {
    if (!pending_) return;
    py::error_already_set error = *pending_;
    pending_.reset();
    throw error;
  }

 private:
  bool quiet_;
  std::unique_ptr<py::error_already_set> pending_;
};

// How a run ended, for Python.
struct RunSummary {
  std::string status;  // "completed", "at_rest", "failed", "interrupted"
  std::string out;     // the output folder
  std::size_t frames = 0;
  double time = 0.0;  // s, of the last frame written
  double wall_seconds = 0.0;
  std::shared_ptr<SimulationHandle> simulation;
};

// Runs (or resumes) with the GIL released, and turns the result into a RunSummary; raises
// SimulationError for a failed simulation (with the folder written) and re-raises a Ctrl-C.
template <typename Start>
py::object finish_in_python(PythonObserver& observer, Start&& start) {
  RunResult result;
  {
    py::gil_scoped_release release;
    result = start();
  }
  auto summary = std::make_shared<RunSummary>();
  summary->status = std::string(to_string(result.status));
  summary->out = result.out.string();
  summary->frames = result.frames;
  summary->time = result.last_time;
  summary->wall_seconds = result.wall_seconds;
  const std::string failure = result.simulation->failure() ? result.simulation->failure()->message : "";
  summary->simulation = std::make_shared<SimulationHandle>(std::move(result.scene), std::move(result.simulation));
  observer.raise_pending();
  py::object object = py::cast(summary);
  if (summary->status == "failed") {
    raise_simulation_error("simulation failed " + failure + "; the " + std::to_string(summary->frames) +
                               " frames up to t = " + format_number(summary->time) + " s are kept in " + summary->out +
                               " (status \"failed\")",
                           object);
  }
  return object;
}

RenderFlags render_flags(const std::string& render, py::handle size, const std::string& camera, const std::string& mesh,
                         const std::string& show, int samples) {
  RenderFlags flags;
  if (!render.empty()) flags.render = render;
  if (py::isinstance<py::str>(size)) {
    flags.size = size.cast<std::string>();
  } else {
    const py::tuple sides = py::tuple(py::reinterpret_borrow<py::object>(size));
    if (sides.size() != 2) throw py::type_error("size is \"WIDTHxHEIGHT\" or (width, height)");
    flags.size = py::str(sides[0]).cast<std::string>() + "x" + py::str(sides[1]).cast<std::string>();
  }
  flags.camera = camera;
  flags.mesh = mesh;
  flags.show = show;
  flags.samples = std::to_string(samples);
  return flags;
}

py::object run(py::handle scene, py::handle set, py::handle out, const std::string& render, py::handle size,
               const std::string& camera, const std::string& mesh, const std::string& show, int samples,
               py::handle max_memory, bool report, bool quiet) {
  const SceneSpec spec = scene_from(scene, set);
  RunOptions options;
  options.max_memory = max_memory_from(max_memory);
  options.max_memory_source = "max_memory";
  if (!out.is_none()) options.out = py::module_::import("os").attr("fspath")(out).cast<std::string>();
  options.out_source = "out";
  options.render = render_flags(render, size, camera, mesh, show, samples);
  options.report = report;
  options.report_source = "report";
  // summary.json's command_line: how to make the run again.
  std::string call = "clothsim.run(" + py::repr(py::str(spec.name)).cast<std::string>();
  if (!options.out.empty()) call += ", out=" + py::repr(py::str(options.out.string())).cast<std::string>();
  call += ", render=" + py::repr(py::str(options.render.render)).cast<std::string>() + ")";
  options.info = RunInfo{CLOTHSIM_VERSION, "python3: " + call};
  PythonObserver observer(quiet);
  options.observer = &observer;
  return finish_in_python(observer, [&] { return run_scene(spec, options); });
}

py::object resume(py::handle path, py::handle max_memory, bool quiet) {
  RunOptions options;
  options.max_memory = max_memory_from(max_memory);
  options.max_memory_source = "max_memory";
  options.info = RunInfo{CLOTHSIM_VERSION, "python3: clothsim.resume(" + py::repr(path).cast<std::string>() + ")"};
  PythonObserver observer(quiet);
  options.observer = &observer;
  const std::string folder = py::module_::import("os").attr("fspath")(path).cast<std::string>();
  return finish_in_python(observer, [&] { return resume_run(folder, options); });
}

}  // namespace

void bind_run(py::module_& module) {
  py::class_<RunSummary, std::shared_ptr<RunSummary>>(module, "RunResult", "How a run ended and where it wrote.")
      .def_readonly("status", &RunSummary::status, "\"completed\", \"at_rest\", \"failed\" or \"interrupted\".")
      .def_readonly("out", &RunSummary::out, "The output folder.")
      .def_readonly("frames", &RunSummary::frames, "Frames written, frame 0 (the initial state) included.")
      .def_readonly("time", &RunSummary::time, "The simulated time of the last frame written, s.")
      .def_readonly("wall_seconds", &RunSummary::wall_seconds, "The run's wall time, s.")
      .def_readonly("simulation", &RunSummary::simulation, "The Simulation at the last frame written.")
      .def("__repr__", [](const RunSummary& summary) {
        return "<clothsim.RunResult " + summary.status + ": " + std::to_string(summary.frames) +
               " frames to t = " + format_number(summary.time) + " s in '" + summary.out + "'>";
      });

  module.def("run", &run, py::arg("scene"), py::kw_only(), py::arg("set") = py::none(), py::arg("out") = py::none(),
             py::arg("render") = "", py::arg("size") = "1280x720", py::arg("camera") = "auto",
             py::arg("mesh") = "particles", py::arg("show") = "", py::arg("samples") = 4,
             py::arg("max_memory") = py::none(), py::arg("report") = false, py::arg("quiet") = false,
             "Runs `scene` (a Scene or anything load_scene() takes, with its set=) and writes the output folder of "
             "`clothsim run` (default out/<scene name>): positions.npy, velocities.npy, energy.csv, summary.json, "
             "final.obj, scene.json, the connector arrays, the scene's exports and, unless render='none', "
             "final.png and animation.mp4 (render: all, image, video or none; '' is the build's default); with "
             "report=True, report.html (the run in a browser, as `clothsim run --report`). size, "
             "camera, mesh, show and samples are the command's --size, --camera, --mesh, --show and --samples. "
             "Notices go to sys.stderr unless quiet. Returns a RunResult; raises ResourceError for a scene whose "
             "estimate is above 90 % of the memory available or above max_memory (bytes, or a size such as '8G'), "
             "SceneError for other bad input (both before anything is written), OutputError when the folder cannot be "
             "written, SimulationError when the simulation fails "
             "(the folder is kept, status \"failed\"; .result is the RunResult), and KeyboardInterrupt after "
             "finishing the folder (status \"interrupted\") on Ctrl-C.");
  module.def("resume", &resume, py::arg("path"), py::kw_only(), py::arg("max_memory") = py::none(),
             py::arg("quiet") = false,
             "Goes on with a run from its newest checkpoint (a run with output.checkpoint_every), as `clothsim run "
             "--resume PATH`: PATH is its folder, the partial folder a killed run left, or a checkpoint file. "
             "Returns a RunResult, as run().");
}

}  // namespace clothsim::python
