// clothsim.Scene and clothsim.load_scene() (bindings.h).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>

#include <nlohmann/json.hpp>

#include "bindings.h"
#include "core/error.h"
#include "run/run_scene.h"
#include "scene/builtin_scenes.h"
#include "scene/parameters.h"
#include "scene/validate_scene.h"

namespace clothsim::python {
namespace {

py::object json_module() { return py::module_::import("json"); }

// A value JSON can hold: NumPy arrays and scalars become lists and numbers.
py::object plain(py::handle value) {
  if (py::hasattr(value, "tolist")) return value.attr("tolist")();
  return py::reinterpret_borrow<py::object>(value);
}

// What a dict source is called in messages, as a file's name is.
constexpr const char* kDictSource = "scene dict";

}  // namespace

std::string field_text(std::string_view key, py::handle value) {
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (value.is_none()) return "none";
  if (py::isinstance<py::int_>(value)) return py::str(value).cast<std::string>();
  // repr(float) is the shortest text that reads back to the same double.
  if (py::isinstance<py::float_>(value)) return py::repr(value).cast<std::string>();
  // NumPy scalars: integers through __index__, reals through __float__.
  const py::object builtins = py::module_::import("builtins");
  if (py::hasattr(value, "__index__")) return py::str(builtins.attr("int")(value)).cast<std::string>();
  if (py::hasattr(value, "__float__") && !py::hasattr(value, "__len__")) {
    return py::repr(builtins.attr("float")(value)).cast<std::string>();
  }
  const py::object data = plain(value);
  if (find_vector_parameter(key) != nullptr && (py::isinstance<py::list>(data) || py::isinstance<py::tuple>(data))) {
    std::string text;
    for (py::handle component : data) {
      if (!text.empty()) text += ",";
      text += field_text("", component);
    }
    return text;
  }
  return json_module().attr("dumps")(data).cast<std::string>();
}

SceneSpec scene_from(py::handle source, py::handle set) {
  SceneSpec spec;
  std::string name;
  if (py::isinstance<SceneSpec>(source)) {
    spec = source.cast<SceneSpec>();
    name = "scene '" + spec.name + "'";
  } else if (py::isinstance<py::dict>(source)) {
    const std::string text = json_module().attr("dumps")(plain(source)).cast<std::string>();
    spec = parse_scene(text, kDictSource);
    name = kDictSource;
  } else if (py::isinstance<py::str>(source) || py::hasattr(source, "__fspath__")) {
    name = py::module_::import("os").attr("fspath")(source).cast<std::string>();
    py::gil_scoped_release release;  // a mesh collider's file can take a while to read
    spec = load_scene(name);
  } else {
    throw py::type_error("a scene is a built-in name, a file path, a dict in the scene file's format or a Scene, got " +
                         py::str(py::type::of(source).attr("__name__")).cast<std::string>());
  }
  if (!set.is_none()) {
    if (!py::isinstance<py::dict>(set)) throw py::type_error("set= takes a dict {key: value} (clothsim.parameters())");
    for (const auto& [key, value] : py::reinterpret_borrow<py::dict>(set)) {
      if (!py::isinstance<py::str>(key)) throw py::type_error("set= keys are dotted scene keys such as 'output.fps'");
      const std::string field = key.cast<std::string>();
      set_scene_field(spec, field, field_text(field, value), "set");
    }
    validate_scene(spec, name + " with set");
  }
  return spec;
}

void bind_scene(py::module_& module) {
  py::class_<SceneSpec>(module, "Scene",
                        "A scene: everything needed to reproduce a run (docs/scene-format.md). Made by "
                        "load_scene(); to_dict() is its scene file.")
      .def_property_readonly("name", [](const SceneSpec& spec) { return spec.name; })
      .def_property_readonly("description", [](const SceneSpec& spec) { return spec.description; })
      .def_property_readonly("rows", [](const SceneSpec& spec) { return spec.lattice.rows; })
      .def_property_readonly("cols", [](const SceneSpec& spec) { return spec.lattice.cols; })
      .def_property_readonly(
          "particles", [](const SceneSpec& spec) { return spec.lattice.rows * spec.lattice.cols; },
          "Particles in the lattice: particle (i, j) has index i * cols + j.")
      .def_property_readonly("fps", [](const SceneSpec& spec) { return spec.output.fps; })
      .def_property_readonly("duration", [](const SceneSpec& spec) { return spec.output.duration; })
      .def_property_readonly(
          "frames", [](const SceneSpec& spec) { return last_frame(spec.output) + 1; },
          "Output frames of a run that goes the whole duration, frame 0 (the initial state) included.")
      .def(
          "frame_times",
          [](const SceneSpec& spec) {
            py::array_t<double> times(static_cast<py::ssize_t>(last_frame(spec.output) + 1));
            auto view = times.mutable_unchecked<1>();
            for (py::ssize_t k = 0; k < view.shape(0); ++k) {
              view(k) = frame_time(static_cast<std::uint64_t>(k), spec.output.fps);
            }
            return times;
          },
          "The times of the output frames, s: [frames] float64, k / fps (clothsim.frame_time).")
      .def(
          "to_dict", [](const SceneSpec& spec) { return json_module().attr("loads")(scene_to_json(spec).dump()); },
          "The scene in the scene file's format; load_scene() takes it back.")
      .def(
          "to_json", [](const SceneSpec& spec, int indent) { return scene_to_json(spec).dump(indent); },
          py::arg("indent") = 2, "The scene file's text.")
      .def("__eq__",
           [](const SceneSpec& a, const SceneSpec& b) { return scene_to_json(a).dump() == scene_to_json(b).dump(); })
      .def("__repr__", [](const SceneSpec& spec) {
        return "<clothsim.Scene '" + spec.name + "': " + std::to_string(spec.lattice.rows) + "x" +
               std::to_string(spec.lattice.cols) + " lattice, " + std::string(to_string(spec.integrator.kind)) + ", " +
               format_number(spec.output.duration) + " s at " + std::to_string(spec.output.fps) + " fps>";
      });

  module.def("load_scene", &scene_from, py::arg("source"), py::kw_only(), py::arg("set") = py::none(),
             "A scene from a built-in name (clothsim.builtin_scenes()), a scene file's path, a dict in the scene "
             "file's format or a Scene (copied). set={key: value, ...} then sets scene fields in order, as "
             "`clothsim run --set key=value` does (keys: clothsim.parameters()), and the scene is checked as a "
             "whole. Raises SceneError naming the source and the field.");
}

}  // namespace clothsim::python
