// clothsim.Simulation (bindings.h): a scene's simulation (scene/scene_simulation.h), stepped from
// Python with the GIL released, its state copied into NumPy arrays, and pictures of it.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <cstring>
#include <span>
#include <string>
#include <string_view>

#include "bindings.h"
#include "core/error.h"
#include "core/record_fields.h"
#include "run/run_scene.h"
#include "run/run_writer.h"
#include "scene/builtin_scenes.h"
#include "scene/parameters.h"
#include "scene/scene_simulation.h"
#include "scene/validate_scene.h"
#include "sim/precision_choice.h"

#if CLOTHSIM_HAVE_RENDER
#include "render/image.h"
#endif

namespace clothsim::python {

SimulationHandle::SimulationHandle(SceneSpec scene_spec, std::unique_ptr<Simulation> made)
    : scene(std::move(scene_spec)), simulation(std::move(made)) {}

std::unique_lock<std::mutex> SimulationHandle::lock() {
  std::unique_lock<std::mutex> held(mutex, std::defer_lock);
  py::gil_scoped_release release;
  held.lock();
  return held;
}

namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 is three doubles, as NumPy sees it");

// A copy of `values` as a NumPy (n, 3) float64 array.
py::array_t<double> copy_vectors(std::span<const Vec3> values) {
  py::array_t<double> array({static_cast<py::ssize_t>(values.size()), py::ssize_t{3}});
  if (!values.empty()) std::memcpy(array.mutable_data(), values.data(), values.size() * sizeof(Vec3));
  return array;
}

// Raises SimulationError with the command's message for a failed simulation.
[[noreturn]] void raise_failure(const Simulation& simulation) {
  std::string message = "simulation failed ";
  message += simulation.failure() ? simulation.failure()->message : std::string("without a diagnosis");
  raise_simulation_error(message);
}

// Advances to `time`; the caller holds the handle's lock.
void advance_locked(SimulationHandle& handle, double time) {
  Simulation& simulation = *handle.simulation;
  if (!std::isfinite(time) || time < simulation.state().time) {
    throw py::value_error("advance_to: the time must be a number >= the current time, t = " +
                          format_number(simulation.state().time) + " s; got " + format_number(time));
  }
  bool ok = false;
  {
    py::gil_scoped_release release;
    ok = simulation.advance_to(time);
  }
  if (!ok) raise_failure(simulation);
}

void advance(SimulationHandle& handle, double time) {
  const std::unique_lock<std::mutex> lock = handle.lock();
  advance_locked(handle, time);
}

// The next output frame after the current time: the least k with frame_time(k, fps) > time.
std::uint64_t next_frame(double time, int fps) {
  auto frame = static_cast<std::uint64_t>(std::max(0.0, std::floor(time * fps)));
  while (frame > 0 && frame_time(frame - 1, fps) > time) --frame;
  while (frame_time(frame, fps) <= time) ++frame;
  return frame;
}

// A record's fields into a dict, in the record's order (core/record_fields.h).
template <typename Record>
void add_fields(py::dict& dict, const Record& record) {
  Record::for_each_field(record, [&dict](std::string_view name, auto&& field, auto...) {
    dict[py::str(std::string(name))] = field_value(field);
  });
}

py::dict energy_terms(const Simulation& simulation) {
  py::dict terms;
  // The time, then the balance's fields as energy.csv and summary.json name them.
  terms["time"] = simulation.state().time;
  add_fields(terms, simulation.energy_balance());
  return terms;
}

py::dict statistics(const Simulation& simulation) {
  py::dict table;
  add_fields(table, simulation.integrator_stats());
  add_fields(table, simulation.model_changes());
  add_fields(table, simulation.contact_statistics());
  add_fields(table, simulation.precision_choice().stats());
  table["threads"] = simulation.threads();
  return table;
}

// Live edits, as the viewer's scripts make them (scene/scene_simulation.h).
void set_live(SimulationHandle& handle, const py::dict& values) {
  const std::unique_lock<std::mutex> lock = handle.lock();
  SceneSpec edited = handle.scene;
  for (const auto& [key, value] : values) {
    const std::string field = py::str(key).cast<std::string>();
    if (!is_live_parameter(field)) {
      throw InputError("set", field, "cannot change while the simulation runs; live keys: " + live_parameter_list());
    }
    set_scene_field(edited, field, field_text(field, value), "set");
  }
  validate_scene(edited, "set");
  apply_live_parameters(handle.scene, edited, *handle.simulation);
  handle.scene = std::move(edited);
}

py::array_t<std::uint8_t> render(SimulationHandle& handle, int width, int height, const std::string& camera,
                                 const std::string& mesh, const std::string& show, int samples) {
#if !CLOTHSIM_HAVE_RENDER
  throw OutputError("this clothsim was built without rendering (CLOTHSIM_BUILD_RENDER=OFF): there are no pictures");
#endif
  RenderFlags flags;
  flags.render = "image";
  flags.size = std::to_string(width) + "x" + std::to_string(height);
  flags.camera = camera;
  flags.mesh = mesh;
  flags.show = show;
  flags.samples = std::to_string(samples);
  const std::shared_ptr<const RenderPlan> plan = parse_render_flags(flags);
  const std::unique_lock<std::mutex> lock = handle.lock();
#if CLOTHSIM_HAVE_RENDER
  {
    py::gil_scoped_release release;
    const std::string settings = render_flags_json(flags);
    if (!handle.renderer || handle.renderer_settings != settings) {
      handle.renderer.reset();
      handle.renderer_settings.clear();
      handle.renderer = std::make_unique<FrameRenderer>(plan);
      handle.renderer_settings = settings;
    }
    // Current on no thread afterwards, whatever happens: the next call may come from another.
    struct Release {
      FrameRenderer& renderer;
      ~Release() { renderer.release(); }
    } release_context{*handle.renderer};
    const Simulation& simulation = *handle.simulation;
    handle.renderer->draw(simulation.model(), simulation.state().position, simulation.state().time);
  }
  const render::Image& image = handle.renderer->image();
  py::array_t<std::uint8_t> pixels(
      {static_cast<py::ssize_t>(image.height), static_cast<py::ssize_t>(image.width), py::ssize_t{3}});
  std::memcpy(pixels.mutable_data(), image.rgb.data(), image.rgb.size());
  return pixels;
#else
  return {};
#endif
}

// A method that reads the simulation: `read(handle)` under the handle's lock.
template <typename Read>
auto locked(Read read) {
  return [read](SimulationHandle& handle) {
    const std::unique_lock<std::mutex> lock = handle.lock();
    return read(handle);
  };
}

}  // namespace

void bind_simulation(py::module_& module) {
  py::class_<SimulationHandle, std::shared_ptr<SimulationHandle>>(
      module, "Simulation",
      "A scene's simulation, as `clothsim run` steps it (make_simulation). positions and velocities are copies, "
      "(particles, 3) float64; particle (i, j) has index i * cols + j. Stepping and rendering release the GIL; "
      "calls on one Simulation from several threads take turns.")
      .def(py::init([](py::handle scene, py::handle set, py::handle max_memory) {
             SceneSpec spec = scene_from(scene, set);
             const MemoryAllowance memory{max_memory_from(max_memory), "max_memory", false};
             std::unique_ptr<Simulation> simulation;
             {
               py::gil_scoped_release release;
               simulation = make_unique_simulation(spec, memory);
             }
             return std::make_shared<SimulationHandle>(std::move(spec), std::move(simulation));
           }),
           py::arg("scene"), py::kw_only(), py::arg("set") = py::none(), py::arg("max_memory") = py::none(),
           "Builds the simulation of `scene` (a Scene, or anything load_scene() takes, with its set=) at its "
           "initial state, t = 0. A scene whose estimated memory is above 90 % of what is available, or above "
           "max_memory (bytes, or a size such as '8G'), raises ResourceError before anything is allocated.")
      .def("advance_to", &advance, py::arg("time"),
           "Advances to exactly `time`, s (>= time). Raises SimulationError if the simulation fails; it then "
           "stays at its last good state.")
      .def(
          "step",
          [](SimulationHandle& handle, int frames) {
            if (frames < 1) throw py::value_error("step: frames must be >= 1, got " + std::to_string(frames));
            const std::unique_lock<std::mutex> lock = handle.lock();
            const int fps = handle.scene.output.fps;
            const std::uint64_t frame =
                next_frame(handle.simulation->state().time, fps) + static_cast<std::uint64_t>(frames - 1);
            advance_locked(handle, frame_time(frame, fps));
          },
          py::arg("frames") = 1,
          "Advances to the next output frame of the scene's fps (or `frames` frames on): from t = 0, n calls "
          "give frame n of `clothsim run`'s positions.npy, bit for bit.")
      .def_property_readonly("time", locked([](SimulationHandle& handle) { return handle.simulation->state().time; }),
                             "The simulated time, s.")
      .def_property_readonly("positions", locked([](SimulationHandle& handle) {
                               return copy_vectors(handle.simulation->state().position);
                             }),
                             "A copy of the particles' positions, m: (particles, 3) float64.")
      .def_property_readonly("velocities", locked([](SimulationHandle& handle) {
                               return copy_vectors(handle.simulation->state().velocity);
                             }),
                             "A copy of the particles' velocities, m/s: (particles, 3) float64.")
      .def("energy", locked([](SimulationHandle& handle) { return energy_terms(*handle.simulation); }),
           "The energies and works now, J, named as energy.csv's columns (time, kinetic, gravitational, "
           "connector, radial_adjacent, radial_opposite, total, damping_work, drag_work, anchor_work, "
           "balance_error, plastic_work, fracture_work, contact_work), with edit_work and initial_total: "
           "balance_error = total - (initial_total + the works).")
      .def("statistics", locked([](SimulationHandle& handle) { return statistics(*handle.simulation); }),
           "Steps, force evaluations, broken springs, plastic strain and contacts so far.")
      .def_property_readonly("failure", locked([](SimulationHandle& handle) -> py::object {
                               const auto& failure = handle.simulation->failure();
                               if (!failure) return py::none();
                               return py::str(failure->message);
                             }),
                             "None, or the diagnosis of the failure that stopped the simulation.")
      .def_property_readonly("scene", locked([](SimulationHandle& handle) { return handle.scene; }),
                             "The scene, with the live edits made by set().")
      .def_property_readonly("particles",
                             [](SimulationHandle& handle) { return handle.simulation->model().particle_count(); })
      .def_property_readonly("rows", [](SimulationHandle& handle) { return handle.simulation->model().rows; })
      .def_property_readonly("cols", [](SimulationHandle& handle) { return handle.simulation->model().cols; })
      .def("set", &set_live, py::arg("values"),
           "Changes live parameters between steps ({key: value}; clothsim.live_parameters()), checked as a "
           "whole; the energy they add is booked as edit_work. Raises SceneError and changes nothing for a key "
           "that is not live or a bad value.")
      .def("render", &render, py::arg("width") = 640, py::arg("height") = 480, py::kw_only(),
           py::arg("camera") = "auto", py::arg("mesh") = "particles", py::arg("show") = "", py::arg("samples") = 4,
           "A picture of the sheet now, headless (EGL; Mesa's llvmpipe without a GPU): (height, width, 3) uint8, "
           "row 0 at the top. camera, mesh, show and samples are `clothsim run`'s --camera, --mesh, --show and "
           "--samples; the camera frames everything drawn so far by calls with the same settings, as a run's "
           "video does.")
      .def("__repr__", [](SimulationHandle& handle) {
        const std::unique_lock<std::mutex> lock = handle.lock();
        return "<clothsim.Simulation '" + handle.scene.name + "': " + std::to_string(handle.scene.lattice.rows) + "x" +
               std::to_string(handle.scene.lattice.cols) +
               " lattice, t = " + format_number(handle.simulation->state().time) + " s" +
               (handle.simulation->failure() ? ", failed" : "") + ">";
      });
}

}  // namespace clothsim::python
