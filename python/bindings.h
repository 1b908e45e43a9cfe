// The Python module `clothsim` (docs/python.md), in pybind11: what its files share.
//
// module.cpp       the module, its exceptions and small functions (builtin_scenes, frame_time)
// scene.cpp        clothsim.Scene (a SceneSpec) and load_scene(): built-in names, files, dicts, set=
// simulation.cpp   clothsim.Simulation: make_simulation(), advance_to, positions, energy, render
// run.cpp          clothsim.run(): the library's run driver (run/run_scene.h), the command's folder
// sweep.cpp        clothsim.sweep(): the command's sweep plan (run/sweep_plan.h), its runs as tasks,
//                  here or on a Dask cluster
//
// Errors: the library's exceptions become Python ones with the same message text (module.cpp):
// ResourceError -> clothsim.ResourceError (a MemoryError, with .estimate, .parts and .limit),
// InputError -> clothsim.SceneError (a ValueError, with .source, .field and .reason),
// OutputError -> clothsim.OutputError (an OSError), a failed simulation -> clothsim.SimulationError
// (a RuntimeError).
//
// Threads: every call that simulates or renders releases the GIL; a Simulation serialises its own
// calls with a mutex, taken only with the GIL released, so that a thread waiting for it never
// holds up the others.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include <pybind11/pybind11.h>

#include "run/render_plan.h"
#include "scene/scene.h"
#include "sim/simulation.h"

namespace clothsim::python {

namespace py = pybind11;

// A scene from what load_scene() takes: a Scene (copied), a built-in name or a file path (str or
// os.PathLike), or a dict in the scene file's format; then the `set` assignments (a dict, or None)
// applied in order as `clothsim run --set` applies them, and the whole scene validated. Throws
// InputError.
SceneSpec scene_from(py::handle source, py::handle set);

// The text set_scene_field() takes for a Python value of field `key`: str as it is, bool as
// true/false, None as none, numbers as the shortest text that reads back exactly, a sequence as
// x,y,z for a vector field and JSON otherwise, a dict as JSON.
std::string field_text(std::string_view key, py::handle value);

// The max_memory= argument: None (90 % of the memory available), a number of bytes, or a size as
// the command's --max-memory takes it ("8G", "512M"). Throws InputError naming max_memory.
std::optional<std::uint64_t> max_memory_from(py::handle value);

// clothsim.Simulation: the scene it was made from (with live edits) and the simulation.
struct SimulationHandle {
  SimulationHandle(SceneSpec scene_spec, std::unique_ptr<Simulation> made);

  SceneSpec scene;
  std::unique_ptr<Simulation> simulation;
  std::mutex mutex;  // one call at a time; locked with the GIL released (lock())
  // Simulation.render(): the renderer of the last call's settings, kept for the next call with
  // the same ones (its camera frames everything drawn so far, as a run's pictures do).
  std::unique_ptr<FrameRenderer> renderer;
  std::string renderer_settings;

  // Locks `mutex`, waiting without the GIL.
  std::unique_lock<std::mutex> lock();
};

// Raises clothsim.SimulationError with `message`; `result`, if not None, becomes its .result.
[[noreturn]] void raise_simulation_error(const std::string& message, py::handle result = py::none());

void bind_scene(py::module_& module);
void bind_simulation(py::module_& module);
void bind_run(py::module_& module);
void bind_sweep(py::module_& module);

}  // namespace clothsim::python
