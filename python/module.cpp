// The Python module `clothsim`: the module itself, its exceptions and its small functions
// (bindings.h has the plan; docs/python.md the API).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <exception>
#include <optional>
#include <string>

#include "bindings.h"
#include "core/error.h"
#include "core/memory_size.h"
#include "run/run_scene.h"
#include "run/run_writer.h"
#include "scene/builtin_scenes.h"
#include "scene/parameters.h"

namespace clothsim::python {
namespace {

// The exception types, created with the module and kept for its life (the interpreter's).
py::handle g_scene_error;
py::handle g_resource_error;
py::handle g_output_error;
py::handle g_simulation_error;

// Raises an instance of `type` with `message` and the given attributes.
void set_error(py::handle type, const std::string& message, const py::dict& attributes = {}) {
  py::object error = type(message);
  for (const auto& [name, value] : attributes) error.attr(name) = value;
  PyErr_SetObject(type.ptr(), error.ptr());
}

// By value: the signature pybind11::register_exception_translator takes.
void translate(std::exception_ptr pointer) {  // NOLINT(performance-unnecessary-value-param)
  try {
    if (pointer) std::rethrow_exception(pointer);
  } catch (const ResourceError& error) {
    py::dict parts;
    for (const ResourceError::Part& part : error.parts()) parts[py::str(part.name)] = part.bytes;
    py::dict attributes;
    attributes["estimate"] = error.estimate_bytes();
    attributes["parts"] = parts;
    attributes["limit"] = error.limit_bytes();
    set_error(g_resource_error, error.what(), attributes);
  } catch (const InputError& error) {
    py::dict attributes;
    attributes["source"] = error.source();
    attributes["field"] = error.field();
    attributes["reason"] = error.reason();
    set_error(g_scene_error, error.what(), attributes);
  } catch (const OutputError& error) {
    set_error(g_output_error, error.what());
  }
}

py::dict builtin_scene_table() {
  py::dict scenes;
  for (const BuiltinScene& scene : builtin_scenes()) scenes[py::str(scene.name)] = scene.description;
  return scenes;
}

// One registry entry as a dict (scene/parameters.h).
py::dict parameter_entry(std::string_view type, std::string_view unit, const ValueRange& range,
                         std::string_view description, bool live) {
  py::dict entry;
  entry["type"] = std::string(type);
  entry["unit"] = std::string(unit);
  entry["min"] = range.min;
  entry["max"] = range.max;
  entry["range"] = describe_range(range);
  entry["description"] = std::string(description);
  entry["live"] = live;
  return entry;
}

py::dict parameter_table() {
  py::dict table;
  for (const ScalarParameter& parameter : scalar_parameters()) {
    std::string_view type = "real";
    if (parameter.type == ParameterType::integer) type = "integer";
    if (parameter.type == ParameterType::boolean) type = "boolean";
    if (parameter.type == ParameterType::limit) type = "limit";
    table[py::str(std::string(parameter.key))] =
        parameter_entry(type, parameter.unit, parameter.range, parameter.description, parameter.live);
  }
  for (const VectorParameter& parameter : vector_parameters()) {
    table[py::str(std::string(parameter.key))] =
        parameter_entry("vector", parameter.unit, parameter.component_range, parameter.description, parameter.live);
  }
  return table;
}

}  // namespace

std::optional<std::uint64_t> max_memory_from(py::handle value) {
  if (value.is_none()) return std::nullopt;
  // The command's forms, and a plain int of bytes (not a bool, which Python counts as an int).
  std::optional<std::uint64_t> bytes;
  std::string text;
  if (py::isinstance<py::int_>(value) && !py::isinstance<py::bool_>(value)) {
    text = py::str(value).cast<std::string>();
    if (value.cast<py::int_>() > py::int_(0)) bytes = parse_memory_size(text);
  } else if (py::isinstance<py::str>(value)) {
    text = value.cast<std::string>();
    bytes = parse_memory_size(text);
  } else {
    text = py::repr(value).cast<std::string>();
  }
  if (!bytes) throw InputError("max_memory", "", "must be " + std::string(memory_size_forms()) + ", got " + text);
  return bytes;
}

void raise_simulation_error(const std::string& message, py::handle result) {
  py::dict attributes;
  attributes["result"] = result;
  set_error(g_simulation_error, message, attributes);
  throw py::error_already_set();
}

}  // namespace clothsim::python

PYBIND11_MODULE(clothsim, module) {
  using namespace clothsim;
  using namespace clothsim::python;
  module.doc() =
      "clothsim: thin sheets on a mass-spring lattice with radial springs (docs/python.md).\n\n"
      "    scene = clothsim.load_scene('paper-fig5', set={'output.fps': 30})\n"
      "    sim = clothsim.Simulation(scene)\n"
      "    sim.advance_to(1.0)\n"
      "    sim.positions            # NumPy (particles, 3) float64, a copy\n"
      "    clothsim.run(scene, out='out/fig5', render='none')   # the output folder of `clothsim run`";
  module.attr("__version__") = CLOTHSIM_VERSION;
#if CLOTHSIM_HAVE_RENDER
  module.attr("has_render") = true;
#else
  module.attr("has_render") = false;
#endif

  // Leaked on purpose: the types live as long as the interpreter, and a static py::object would be
  // destroyed after it.
  g_scene_error = PyErr_NewExceptionWithDoc(
      "clothsim.SceneError",
      "Bad input: a scene, a value of set= or an argument. The message is the command's; .source names where "
      "the value came from, .field the dotted scene key (may be empty), .reason what is allowed.",
      PyExc_ValueError, nullptr);
  g_resource_error = PyErr_NewExceptionWithDoc(
      "clothsim.ResourceError",
      "A scene too large for the memory this process may use, refused before anything was allocated or written. "
      "The message is the command's; .estimate is the estimated bytes, .parts their breakdown (a dict of bytes), "
      ".limit the most the estimate could be (90 % of the memory available, or max_memory=).",
      PyExc_MemoryError, nullptr);
  g_output_error = PyErr_NewExceptionWithDoc("clothsim.OutputError",
                                             "The output (a run's folder, a picture) could not be written or made.",
                                             PyExc_OSError, nullptr);
  g_simulation_error = PyErr_NewExceptionWithDoc(
      "clothsim.SimulationError",
      "The simulation failed (blew up, needed a step below the floor) and stopped at its last good state; the "
      "message is the diagnosis. From clothsim.run(), .result is the RunResult (the folder is written, with "
      "status \"failed\").",
      PyExc_RuntimeError, nullptr);
  if (g_scene_error.ptr() == nullptr || g_resource_error.ptr() == nullptr || g_output_error.ptr() == nullptr ||
      g_simulation_error.ptr() == nullptr) {
    throw py::error_already_set();
  }
  module.attr("SceneError") = g_scene_error;
  module.attr("ResourceError") = g_resource_error;
  module.attr("OutputError") = g_output_error;
  module.attr("SimulationError") = g_simulation_error;
  py::register_exception_translator(translate);

  module.def("builtin_scenes", &builtin_scene_table,
             "The built-in scenes, {name: description}; each is also a name load_scene() takes.");
  module.def("parameters", &parameter_table,
             "Every scalar and vector scene parameter of the registry, {key: {type, unit, min, max, range, "
             "description, live}}; the keys are those of load_scene(set=...) and Simulation.set().");
  module.def(
      "live_parameters",
      [] { return std::vector<std::string>(live_parameter_keys().begin(), live_parameter_keys().end()); },
      "The keys Simulation.set() may change while the simulation runs.");
  module.def("frame_time", &frame_time, py::arg("frame"), py::arg("fps"),
             "The simulated time of output frame `frame` at `fps` frames per second, s: frame / fps, exactly as "
             "`clothsim run` computes it (advance_to(frame_time(k, fps)) lands on the run's frame k bit for bit).");

  bind_scene(module);
  bind_simulation(module);
  bind_run(module);
  bind_sweep(module);
}
