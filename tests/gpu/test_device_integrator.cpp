// The Vulkan backend's integrator (gpu/device_integrator.h, --backend vulkan) on the machine's
// Vulkan device (lavapipe on CI), against the CPU's integrators: one step, the paper's scenes,
// the energy balance, free flight, anchors on paths, edits between frames, and the failures.
#include "gpu/device_integrator.h"
#include "gpu/gpu_error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <tuple>
#include <vector>

#include "device_models.h"
#include "events/spring_events.h"
#include "integrators/integrator.h"
#include "model/cloth_model.h"
#include "model/model_edits.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene/scene_simulation.h"
#include "scene/validate_scene.h"
#include "scene_simulation.h"
#include "sim/backend.h"
#include "sim/simulation.h"

namespace clothsim {
namespace {

using testing::largest_distance;
using testing::paper_lattice;
using testing::run_scene_to;
using testing::RunEnd;
using testing::vulkan;

// Device 0 with the validation layers, where installed (tests/gpu/gpu_fixture.h).
gpu::DeviceSelection device0(Precision precision) { return gpu::DeviceSelection{0, precision, true}; }

// A built-in scene the backend runs: paper-fig4 without its self-collision (the paper had none).
SceneSpec device_scene(const char* name, const BackendSettings& backend) {
  SceneSpec spec = builtin_scene(name);
  spec.collision.self = false;
  spec.backend = backend;
  return spec;
}

TEST(DeviceIntegrator, OneStepIsTheCpusInFloat64) {
  // One step from a moving sheet: the same stage sums in the same order, the same element
  // formulas, the same gather order; only the work sums and atan2 differ (docs/gpu.md).
  const ClothModel model = paper_lattice(9, 9);
  for (IntegratorKind kind : {IntegratorKind::symplectic_euler, IntegratorKind::rk4, IntegratorKind::rkf45}) {
    IntegratorSettings settings;
    settings.kind = kind;
    settings.time_step = 1e-4;
    ClothState cpu;
    cpu.position = model.particle_rest_position;
    cpu.velocity.assign(model.particle_count(), Vec3{});
    for (std::size_t p = 0; p < cpu.velocity.size(); ++p) cpu.velocity[p] = {0.01 * double(p % 7), 0.2, -0.03};
    ClothState device = cpu;
    const ForceOptions options;
    std::unique_ptr<Integrator> reference = make_integrator(model, settings, options);
    gpu::DeviceIntegrator integrator(model, settings, options, device0(Precision::float64));
    ASSERT_EQ(reference->step(cpu, 1.0).status, StepStatus::ok);
    ASSERT_EQ(integrator.step(device, 1.0).status, StepStatus::ok);
    EXPECT_EQ(cpu.time, device.time) << to_string(kind);
    EXPECT_LT(largest_distance(cpu.position, device.position), 1e-15) << to_string(kind);
    EXPECT_LT(largest_distance(cpu.velocity, device.velocity), 1e-13) << to_string(kind);
    EXPECT_NEAR(cpu.damping_work, device.damping_work, 1e-12 * std::abs(cpu.damping_work)) << to_string(kind);
    EXPECT_EQ(integrator.stats().accepted_steps, 1u);
  }
}

// The paper's three scenes (paper-fig4 without self-collision) for a quarter second against the
// CPU's RKF45 at the default tolerances (rtol = atol = 1e-6, on positions of up to 10 m). In
// float64 the two take nearly the same steps and differ by the error control's slack, of the
// order of rtol |x| = 1e-5 m (measured 9e-7 m, velocities 1.5e-5 m/s). In float32 every force
// carries rounding of eps_f (6e-8) times its scale, and the accepted state the rounding of
// eps_f |x| (6e-7 m), which the error control sees as error: 2 to 6 % more steps (the stages,
// offsets from the step's start, add none: gpu/shaders/stage_offsets.glsl), and trajectories
// apart by up to 2.4e-4 m and 0.0104 m/s (measured), against speeds of 2.5 m/s. The energy
// balance closes as well: within 1e-11 of the energy scale in float64 (as the CPU), 1e-8 in
// float32 (measured 2e-11 and 7e-9).
TEST(DeviceIntegrator, PaperScenesFollowTheCpu) {
  for (const char* name : {"paper-fig4", "paper-fig5", "paper-fig6"}) {
    const RunEnd cpu = run_scene_to(device_scene(name, BackendSettings{}), 0.25);
    for (Precision precision : {Precision::float64, Precision::float32}) {
      const RunEnd device = run_scene_to(device_scene(name, vulkan(precision)), 0.25);
      const bool f64 = precision == Precision::float64;
      const double distance = largest_distance(cpu.position, device.position);
      const double speed_difference = largest_distance(cpu.velocity, device.velocity);
      std::printf(
          "%s %s: largest distance %.3g m, velocity %.3g m/s; steps %llu vs %llu; balance %.3g vs %.3g J (%.2g of "
          "the energy scale)\n",
          name, to_string(precision), distance, speed_difference,
          static_cast<unsigned long long>(device.stats.accepted_steps),
          static_cast<unsigned long long>(cpu.stats.accepted_steps), device.balance_error, cpu.balance_error,
          std::abs(device.balance_error) / device.energy_scale);
      EXPECT_LT(distance, f64 ? 1e-5 : 2e-3) << name << " " << to_string(precision);
      EXPECT_LT(speed_difference, f64 ? 1e-4 : 0.05) << name << " " << to_string(precision);
      EXPECT_LT(std::abs(device.balance_error), (f64 ? 1e-10 : 1e-7) * device.energy_scale)
          << name << " " << to_string(precision);
      EXPECT_NEAR(static_cast<double>(device.stats.accepted_steps), static_cast<double>(cpu.stats.accepted_steps),
                  (f64 ? 0.02 : 0.3) * static_cast<double>(cpu.stats.accepted_steps));
    }
  }
}

// free-spin: no anchors, gravity or drag, so the sheet's momentum and angular momentum stay what
// they were. Momentum: each element's forces sum to zero, so only their rounding moves it, against
// the scale sum m |v| (measured after 0.5 s: 1.9 eps of it in float64, 1.6 eps_f in float32). Angular momentum: RKF45's
// truncation error moves it too (1.4e-12 of |L| in float64, the CPU's figure), and in float32 the rounding of some
// thousand steps (1.4e-5 of |L|, 230 eps_f).
TEST(DeviceIntegrator, FreeFlightKeepsMomentumAndAngularMomentum) {
  for (Precision precision : {Precision::float64, Precision::float32}) {
    SceneSpec spec = builtin_scene("free-spin");
    spec.backend = vulkan(precision);
    Simulation simulation = make_simulation(spec);
    struct Momenta {
      Vec3 linear, angular;
      double linear_scale = 0.0;
    };
    const auto momenta = [&] {
      Momenta m;
      const ClothState& state = simulation.state();
      for (std::size_t p = 0; p < state.position.size(); ++p) {
        const double mass = simulation.model().particle_mass[p];
        m.linear += mass * state.velocity[p];
        m.angular += cross(state.position[p], mass * state.velocity[p]);
        m.linear_scale += mass * norm(state.velocity[p]);
      }
      return m;
    };
    const Momenta before = momenta();
    ASSERT_TRUE(simulation.advance_to(0.5)) << simulation.failure()->message;
    const Momenta after = momenta();
    const bool f64 = precision == Precision::float64;
    const double eps = f64 ? 0x1p-52 : 0x1p-23;
    std::printf("%s: momentum drift %.3g of scale %.3g, angular %.3g of %.3g\n", to_string(precision),
                norm(after.linear - before.linear), before.linear_scale, norm(after.angular - before.angular),
                norm(before.angular));
    EXPECT_LT(norm(after.linear - before.linear), 16 * eps * before.linear_scale) << to_string(precision);
    EXPECT_LT(norm(after.angular - before.angular), (f64 ? 1e-11 : 1e3 * eps) * norm(before.angular))
        << to_string(precision);
  }
}

// The lattice path (lattice_elements: each particle its own springs, by particle) against the
// general path (element passes and force slots) on a sheet that is not square, torn in places,
// with every spring's rest value and constants its own (as plasticity and creasing leave them),
// moving: one RKF45 step each, in float64, from the same state. The two evaluate the same
// formulas and differ only in the order of the sums: a few ulps. With `collapse`, a few particles
// are moved to 10 % to 40 % of the way from a neighbour (east, south, west and north of them), so
// that the radial springs on those connectors fade (forces/element_math.inc): the lattice path
// takes the fade lengths from each arm's connector, its own or its neighbour's (whose original
// lengths differ here).
// The model's rest state, every particle moved and moving a little.
ClothState moving_state(const ClothModel& model) {
  ClothState state;
  state.position = model.particle_rest_position;
  state.velocity.assign(model.particle_count(), Vec3{});
  for (std::size_t p = 0; p < state.position.size(); ++p) {
    const double s = static_cast<double>(p);
    state.position[p] += Vec3{0.1 * std::sin(s), 0.2 * std::cos(1.3 * s), 0.1 * std::sin(0.7 * s)};
    state.velocity[p] = {0.3 * std::cos(s), 0.1, -0.2 * std::sin(2.1 * s)};
  }
  return state;
}

// Four arms of a 12 x 9 sheet nearly gone, one in each direction: each particle moved most of the
// way to its neighbour.
void collapse_arms(ClothState& state, int cols) {
  // (particle, neighbour, fraction of the way left)
  for (const auto& [p, q, left] : {std::tuple{20, 21, 0.1}, std::tuple{31, 31 + cols, 0.25}, std::tuple{58, 57, 0.4},
                                   std::tuple{84, 84 - cols, 0.15}}) {
    const auto a = static_cast<std::size_t>(p);
    const auto b = static_cast<std::size_t>(q);
    state.position[a] = state.position[b] + left * (state.position[a] - state.position[b]);
  }
}

void expect_lattice_path_is_general_path(bool collapse) {
  ClothModel model = paper_lattice(12, 9);
  ClothState state = moving_state(model);
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    model.connector_rest_length[e] *= 1.0 + 0.01 * std::sin(static_cast<double>(e));
    model.connector_stiffness[e] *= 1.0 + 0.1 * std::cos(static_cast<double>(e));
  }
  for (std::size_t r = 0; r < model.radial_count(); ++r)
    model.radial_rest_angle[r] += 0.05 * std::sin(static_cast<double>(r));
  if (collapse) {
    // Original lengths that differ from connector to connector (as if built so), so that an arm
    // whose fade length came from the wrong connector would show.
    for (std::size_t e = 0; e < model.connector_count(); ++e) {
      model.connector_original_length[e] *= 1.0 + 0.3 * std::sin(2.7 * static_cast<double>(e));
    }
    collapse_arms(state, model.cols);
  }
  for (std::uint32_t e : {5u, 17u, 40u, 41u}) tear_connector(model, state, e);
  IntegratorSettings settings;  // rkf45, first step 1e-3 s
  ForceOptions general;
  general.kernel = ForceKernel::general;
  gpu::DeviceIntegrator lattice_path(model, settings, ForceOptions{}, device0(Precision::float64));
  gpu::DeviceIntegrator general_path(model, settings, general, device0(Precision::float64));
  ASSERT_TRUE(lattice_path.lattice_path());
  ASSERT_FALSE(general_path.lattice_path());
  ClothState a = state;
  ClothState b = state;
  ASSERT_EQ(lattice_path.step(a, 1.0).status, StepStatus::ok);
  ASSERT_EQ(general_path.step(b, 1.0).status, StepStatus::ok);
  EXPECT_EQ(a.time, b.time);
  EXPECT_LT(largest_distance(a.position, b.position), 1e-14);
  EXPECT_LT(largest_distance(a.velocity, b.velocity), 1e-11);
  EXPECT_NEAR(a.damping_work, b.damping_work, 1e-12 * std::abs(b.damping_work));
  EXPECT_LT(a.damping_work, 0.0);
}

TEST(DeviceIntegrator, TheLatticePathIsTheGeneralPath) { expect_lattice_path_is_general_path(false); }

TEST(DeviceIntegrator, TheLatticePathIsTheGeneralPathWhereRadialSpringsFade) {
  expect_lattice_path_is_general_path(true);
}

// A uniform sheet (each kind of spring alike everywhere, and no law that changes them) has every
// particle read one interior particle's springs (LatticePassConstants::params_particle): the
// general path's forces with fewer bytes an attempt. A sheet with one spring of its own, a torn
// one, or one whose springs a law may change reads each particle's own.
TEST(DeviceIntegrator, AUniformSheetReadsOneParticlesSprings) {
  const ClothModel uniform = paper_lattice(12, 9);
  ClothState state = moving_state(uniform);
  collapse_arms(state, uniform.cols);  // radial springs that fade by their arms' original lengths
  const auto one_step = [&](const ClothModel& model, ForceKernel kernel, ClothState& end) {
    ForceOptions options;
    options.kernel = kernel;
    gpu::DeviceIntegrator device(model, IntegratorSettings{}, options, device0(Precision::float64));
    end = state;
    EXPECT_EQ(device.step(end, 1.0).status, StepStatus::ok);
    return std::pair{device.reads_uniform_springs(), device.traffic_per_particle_and_attempt()};
  };
  ClothState lattice_end, general_end;
  const auto [reads_one, traffic] = one_step(uniform, ForceKernel::automatic, lattice_end);
  one_step(uniform, ForceKernel::general, general_end);
  EXPECT_TRUE(reads_one);
  EXPECT_EQ(lattice_end.time, general_end.time);
  EXPECT_LT(largest_distance(lattice_end.position, general_end.position), 1e-14);
  EXPECT_LT(largest_distance(lattice_end.velocity, general_end.velocity), 1e-11);

  ClothModel one_own = uniform;
  one_own.radial_stiffness.back() *= 1.0 + 1e-12;  // a corner's spring
  ClothModel torn = uniform;
  ClothState torn_state = state;
  tear_connector(torn, torn_state, 17);
  ClothModel with_laws = uniform;
  with_laws.limits.yield_strain = 0.5;
  for (const ClothModel* model : {&one_own, &torn, &with_laws}) {
    ClothState end;
    const auto [reads, own_traffic] = one_step(*model, ForceKernel::automatic, end);
    EXPECT_FALSE(reads);
    // Each particle's 32 spring values and its two connectors' original lengths, six stages of
    // float64, more an attempt (with laws the event passes' bytes besides).
    EXPECT_GE(own_traffic, traffic + 6.0 * (gpu::kLatticeParams + 2) * sizeof(double));
  }
}

// A sheet that tears (tearing and the events on the device, lattice_events_*): an 11 x 11 sheet
// of the paper's material held at three points of its top row while keyframes pull its bottom
// corners down 3 m in 0.6 s, connectors breaking at 4 % strain with a 30 % spread. The device
// breaks the same 31 connectors as the CPU in both precisions (float64: within a millisecond of
// the CPU's break times), and books the same fracture work (float64: 1.4e-4 of it).
SceneSpec tearing_sheet(const BackendSettings& backend) {
  SceneSpec spec = scene_from_paper_args("11,11,1,4,1,1400,200,80,5,1", "test");
  set_scene_field(spec, "anchors",
                  R"([{"row": 0, "col": 0}, {"row": 0, "col": 5}, {"row": 0, "col": 10},
                      {"row": 10, "col": 0, "path": {"type": "keyframes", "keys": [[0, 0, 0, 0], [0.6, 0, -3, 0]]}},
                      {"row": 10, "col": 10, "path": {"type": "keyframes", "keys": [[0, 0, 0, 0], [0.6, 0, -3, 0]]}}])",
                  "test");
  set_scene_field(spec, "springs.connector.break_strain", "0.04", "test");
  set_scene_field(spec, "springs.connector.break_strain_variation", "0.3", "test");
  validate_scene(spec, "test");
  spec.backend = backend;
  return spec;
}

TEST(DeviceIntegrator, ATornSheetBreaksTheCpusConnectors) {
  // The CPU in float64 (its default, `auto`, may take float32 forces).
  const RunEnd cpu = run_scene_to(tearing_sheet(BackendSettings{Backend::cpu, 0, PrecisionRequest::float64}), 0.6);
  ASSERT_GT(cpu.events.breaks, 5u) << "the scene tears";
  for (Precision precision : {Precision::float64, Precision::float32}) {
    const RunEnd device = run_scene_to(tearing_sheet(vulkan(precision)), 0.6);
    std::printf("%s: %zu breaks (CPU %zu), fracture work %.6g J (CPU %.6g J)\n", to_string(precision),
                device.events.breaks, cpu.events.breaks, device.fracture_work, cpu.fracture_work);
    EXPECT_EQ(device.live, cpu.live) << to_string(precision) << ": the same connectors broken";
    EXPECT_EQ(device.events.breaks, cpu.events.breaks);
    EXPECT_EQ(device.changes.broken_radials, cpu.changes.broken_radials);
    if (precision == Precision::float64) {
      for (std::size_t e = 0; e < cpu.live.size(); ++e) {
        if (cpu.live[e] == 0) {
          EXPECT_NEAR(device.break_time[e], cpu.break_time[e], 1e-3) << "connector " << e;
        }
      }
      EXPECT_NEAR(device.fracture_work, cpu.fracture_work, 1e-3 * std::abs(cpu.fracture_work));
    }
  }
}

// A sheet that yields and creases: the same pull without breaking, with a yield strain of 2 %
// and hardening 0.5, and radial springs that crease past 2 degrees. The device's rest lengths and
// angles follow the CPU's: the largest plastic strain and rest angle change within 1e-4 (float64)
// and 2e-3 (float32) of the CPU's (measured 8e-5 and 4e-5), the plastic work within 1e-3 and
// 2e-2 (measured 3e-4 and 2e-4). The counts differ more (20,164 and 23,114 yields against the
// CPU's 21,008): a connector at its yield strain yields again at every step whose strain rounds
// just above it, and the steps differ.
TEST(DeviceIntegrator, APlasticSheetStretchesAndCreasesAsOnTheCpu) {
  const auto scene = [](const BackendSettings& backend) {
    SceneSpec spec = tearing_sheet(backend);
    set_scene_field(spec, "springs.connector.break_strain", "none", "test");
    set_scene_field(spec, "springs.connector.yield_strain", "0.02", "test");
    set_scene_field(spec, "springs.connector.hardening", "0.5", "test");
    set_scene_field(spec, "springs.adjacent.yield_angle_deg", "2", "test");
    set_scene_field(spec, "springs.opposite.yield_angle_deg", "2", "test");
    validate_scene(spec, "test");
    return spec;
  };
  const RunEnd cpu = run_scene_to(scene(BackendSettings{}), 0.6);
  ASSERT_GT(cpu.events.yields, 10u);
  ASSERT_GT(cpu.events.creases, 10u);
  for (Precision precision : {Precision::float64, Precision::float32}) {
    const RunEnd device = run_scene_to(scene(vulkan(precision)), 0.6);
    const bool f64 = precision == Precision::float64;
    std::printf(
        "%s: plastic strain %.6g (CPU %.6g), rest angle change %.6g (CPU %.6g), plastic work %.6g J "
        "(CPU %.6g J), yields %zu (CPU %zu), creases %zu (CPU %zu)\n",
        to_string(precision), device.changes.max_plastic_strain, cpu.changes.max_plastic_strain,
        device.changes.max_rest_angle_change, cpu.changes.max_rest_angle_change, device.plastic_work, cpu.plastic_work,
        device.events.yields, cpu.events.yields, device.events.creases, cpu.events.creases);
    EXPECT_NEAR(device.changes.max_plastic_strain, cpu.changes.max_plastic_strain, f64 ? 1e-4 : 2e-3);
    EXPECT_NEAR(device.changes.max_rest_angle_change, cpu.changes.max_rest_angle_change, f64 ? 1e-4 : 2e-3);
    EXPECT_NEAR(device.plastic_work, cpu.plastic_work, (f64 ? 1e-3 : 2e-2) * std::abs(cpu.plastic_work));
    double largest = 0.0;
    for (std::size_t e = 0; e < cpu.rest_length.size(); ++e) {
      largest = std::max(largest, std::abs(device.rest_length[e] - cpu.rest_length[e]) / cpu.rest_length[e]);
    }
    EXPECT_LT(largest, f64 ? 1e-4 : 2e-3) << "rest lengths";
  }
}

// paper-fig5 yielding all the while (yield strain 2e-4) and let go by its anchor at 0.3 s, the end
// of an advance in which connectors yielded: the release reaches the device with the device's own
// changes to the springs. (It once went missing there: the device held the sheet by its centre and
// ended with 342 J of kinetic energy where the CPU's falling sheet has 692 J.)
TEST(DeviceIntegrator, ASheetLetGoWhileItYieldsFallsAsOnTheCpu) {
  const auto run = [](const BackendSettings& backend) {
    SceneSpec spec = builtin_scene("paper-fig5");
    set_scene_field(spec, "springs.connector.yield_strain", "0.0002", "test");
    for (AnchorSpec& anchor : spec.anchors) anchor.release_time = 0.3;
    spec.backend = backend;
    Simulation simulation = testing::one_thread_simulation(spec);
    for (int frame = 1; frame <= 27; ++frame) {
      EXPECT_TRUE(simulation.advance_to(frame / 60.0)) << simulation.failure()->message;
    }
    return simulation;
  };
  const Simulation cpu = run(BackendSettings{});
  const Simulation device = run(vulkan(Precision::float64));
  ASSERT_GT(cpu.event_totals().yields, 1000u);
  EXPECT_TRUE(device.model().anchors.empty());
  EXPECT_NEAR(device.energy().kinetic, cpu.energy().kinetic, 1e-6 * cpu.energy().kinetic);
  // 1.3e-6 m on lavapipe (RKF45's steps round differently on the two sides; without the release,
  // 0.43 m).
  EXPECT_LT(largest_distance(device.state().position, cpu.state().position), 1e-4);
}

// Every anchor path kind, a release, and a keyframed path's velocity jumps at its keys: the
// device's paths are rewritten per advance relative to its start (device_step.h,
// anchor_motion.glsl), and the Simulation stops each advance at the next anchor event, as it
// stops each CPU step there. The sheet is shaken hard (the sinusoid at 3 Hz, 5.6 m/s), so RKF45's
// own global error at the default tolerance reaches a millimetre by 0.4 s: the device must be as
// close as the CPU to a run at tolerance 1e-9 (float64).
TEST(DeviceIntegrator, AnchorsOnPathsAreAsAccurateAsTheCpu) {
  const auto scene = [](const BackendSettings& backend, double tolerance) {
    SceneSpec spec = scene_from_paper_args("9,9,1,4,1,1400,200,80,5,1", "test");
    set_scene_field(spec, "anchors",
                    R"([{"row": 0, "col": 0, "path": {"type": "linear", "velocity": [0.2, 0.1, 0]}},
                        {"row": 0, "col": 8, "path": {"type": "sinusoid", "amplitude": [0, 0.3, 0.1], "frequency": 3,
                                                      "phase": 0.4}},
                        {"row": 8, "col": 0, "path": {"type": "keyframes",
                                                      "keys": [[0, 0, 0, 0], [0.1, 0, 0.2, 0], [0.3, 0.1, 0.2, 0]]}},
                        {"row": 8, "col": 8, "release_time": 0.2}])",
                    "test");
    validate_scene(spec, "test");
    spec.backend = backend;
    spec.integrator.relative_tolerance = spec.integrator.absolute_tolerance = tolerance;
    return spec;
  };
  const RunEnd reference = run_scene_to(scene(BackendSettings{}, 1e-9), 0.4);
  const RunEnd cpu = run_scene_to(scene(BackendSettings{}, 1e-6), 0.4);
  const RunEnd device = run_scene_to(scene(vulkan(Precision::float64), 1e-6), 0.4);
  const double cpu_error = largest_distance(cpu.position, reference.position);
  const double device_error = largest_distance(device.position, reference.position);
  std::printf("error against tolerance 1e-9: cpu %.3g m, device %.3g m\n", cpu_error, device_error);
  EXPECT_LT(device_error, 2 * cpu_error + 1e-6);
  EXPECT_LT(std::abs(device.balance_error), 1e-8 * device.energy_scale);
}

// Edits between frames reach the device: a pinned particle (the state changed on the host), a
// cut (the model's broken springs), a stiffer family and gravity (the model's values). Against
// the CPU making the same edits at the same times, in float64.
TEST(DeviceIntegrator, EditsBetweenFramesReachTheDevice) {
  const auto run = [](const BackendSettings& backend) {
    SceneSpec spec = device_scene("paper-fig5", backend);
    Simulation simulation = make_simulation(spec);
    EXPECT_TRUE(simulation.advance_to(0.1));
    simulation.pin_particle(0);
    EXPECT_TRUE(simulation.advance_to(0.2));
    const std::vector<std::uint32_t> cut = {3, 4, 5, 6};
    EXPECT_EQ(simulation.cut_connectors(cut), 4u);
    simulation.set_spring_parameters(SpringFamily::adjacent, SpringParameters{40.0, 2.0});
    Environment environment = simulation.model().environment;
    environment.gravity = {1.0, -5.0, 0.0};
    simulation.set_environment(environment);
    EXPECT_TRUE(simulation.advance_to(0.35));
    return testing::run_end(simulation);
  };
  const RunEnd cpu = run(BackendSettings{});
  const RunEnd device = run(vulkan(Precision::float64));
  EXPECT_LT(largest_distance(cpu.position, device.position), 1e-5);
  EXPECT_LT(largest_distance(cpu.velocity, device.velocity), 1e-4);
  EXPECT_NEAR(device.balance_error, cpu.balance_error, 1e-10 * device.energy_scale);
}

// The lattice path reads only the stage state, the masses and the environment of DeviceForces:
// the element arrays, the force slots, the gather table and the element powers are the general
// path's alone, and are not allocated for the lattice path (issue 22 item 3). The whole device
// step at 1024 x 1024 in float32 then holds under 500 bytes a particle, the general path over 900.
TEST(DeviceIntegrator, TheLatticePathHoldsNoElementArrays) {
  const LatticeCounts counts = lattice_counts(1024, 1024);
  const auto per_particle = [&](std::uint64_t bytes) {
    return static_cast<double>(bytes) / static_cast<double>(counts.particles);
  };
  const std::uint64_t forces_lattice =
      gpu::DeviceForces::bytes_for(counts, Precision::float32, 6, gpu::DeviceForcePath::lattice);
  EXPECT_LE(per_particle(forces_lattice), 3 * 4 + 3 * 4 + 4 + 0.01);  // position, velocity, mass
  const auto step = [&](gpu::DeviceForcePath path) {
    return per_particle(
        gpu::DeviceIntegrator::device_bytes_for(counts, 1, IntegratorKind::rkf45, Precision::float32, path));
  };
  // Chained three stages a pass, the springs' forces and the last stage's accelerations are not
  // held: 15 + 3 reals a particle fewer.
  const double chained = per_particle(gpu::DeviceIntegrator::device_bytes_for(
      counts, 1, IntegratorKind::rkf45, Precision::float32, gpu::DeviceForcePath::lattice, 0, 3));
  std::printf(
      "the device step at 1024 x 1024 in float32: %.1f bytes a particle (lattice path), %.1f (chained), "
      "%.1f (general)\n",
      step(gpu::DeviceForcePath::lattice), chained, step(gpu::DeviceForcePath::general));
  EXPECT_LT(step(gpu::DeviceForcePath::lattice), 500.0);
  EXPECT_NEAR(step(gpu::DeviceForcePath::lattice) - chained, (15 + 3) * 4.0, 0.5);
  EXPECT_GT(step(gpu::DeviceForcePath::general), 900.0);
  // A device integrator on each path runs, and the one on the lattice path holds the smaller set.
  const ClothModel model = paper_lattice(6, 7);
  ForceOptions general;
  general.kernel = ForceKernel::general;
  const gpu::DeviceIntegrator lattice_path(model, IntegratorSettings{}, ForceOptions{}, device0(Precision::float32));
  EXPECT_TRUE(lattice_path.lattice_path());
  EXPECT_EQ(lattice_path.device_forces_path(), gpu::DeviceForcePath::lattice);
  const gpu::DeviceIntegrator general_path(model, IntegratorSettings{}, general, device0(Precision::float32));
  EXPECT_EQ(general_path.device_forces_path(), gpu::DeviceForcePath::general);
}

// The device's time per stage comes from timestamps between its passes (gpu/pass_timer.h), by
// the CPU's stage names; it lies inside the step's wall time, which the rows then add up to. The
// traffic per particle and attempt is counted from the passes' arrays (issue 22 item 5). In three
// passes a stage, which name the stage sums apart (test_device_fused_stages.cpp has the one pass).
TEST(DeviceIntegrator, TheProfileNamesTheCpusStagesAndTheTraffic) {
  SceneSpec spec = device_scene("paper-fig5", vulkan(Precision::float32));
  spec.backend.stage_passes = StagePasses::split;
  spec.lattice.limits.break_strain = 10.0;  // the event passes run (and never break a spring)
  Simulation simulation = make_simulation(spec);
  ASSERT_TRUE(simulation.advance_to(0.2));
  const StepProfile profile = simulation.profile();
  for (StepStage stage : {StepStage::forces, StepStage::stage_sums, StepStage::solution_and_error,
                          StepStage::solution_update, StepStage::events, StepStage::device_steps}) {
    EXPECT_TRUE(profile.timed(stage)) << to_string(stage);
    EXPECT_GE(profile.seconds(stage), 0.0) << to_string(stage);
  }
  EXPECT_GT(profile.seconds(StepStage::forces), 0.0);
  EXPECT_GT(profile.seconds(StepStage::stage_sums), 0.0);
  // The integration stage is the step's wall time less the forces and the device's events, and
  // its parts fit inside it.
  EXPECT_GE(profile.seconds(StepStage::integration), 0.0);
  const double parts = profile.seconds(StepStage::stage_sums) + profile.seconds(StepStage::solution_and_error) +
                       profile.seconds(StepStage::solution_update) + profile.seconds(StepStage::device_steps);
  EXPECT_LE(parts, profile.seconds(StepStage::integration) * (1.0 + 1e-9) + 1e-6);
  // About 3.2 kB per particle and attempt in float32 (RKF45: six stages of a state, the lattice
  // pass and the gather, then the solution and the acceptance); float64 twice the reals, less what
  // float32 reads and writes besides: the state beside each stage's offsets in the lattice pass and
  // the gather (6 and 3 reals a stage: shaders/stage_offsets.glsl), and the state's low parts in
  // the stage pass (6 a stage), the solution and the acceptance (12 each: shaders/split_state.glsl).
  const auto traffic = [](Precision precision, double break_strain) {
    ClothModel model = paper_lattice(8, 8);
    model.limits.break_strain = break_strain;
    gpu::DeviceSelection split = device0(precision);
    split.stage_passes = StagePasses::split;
    gpu::DeviceIntegrator device(model, IntegratorSettings{}, ForceOptions{}, split);
    ClothState state;  // one step, which sets the passes up for the model's laws
    state.position = model.particle_rest_position;
    state.velocity.assign(model.particle_count(), Vec3{});
    EXPECT_EQ(device.step(state, 0.01).status, StepStatus::ok);
    return device.traffic_per_particle_and_attempt();
  };
  const double single = traffic(Precision::float32, SpringLimits::kNever);
  EXPECT_GT(single, 2000.0);
  EXPECT_LT(single, 3500.0);
  const double float32_only = (6 * (6 + 3 + 6) + 12 + 12) * 4.0;
  EXPECT_GT(traffic(Precision::float64, SpringLimits::kNever), 1.9 * (single - float32_only));
  EXPECT_GT(traffic(Precision::float32, 0.5), single);  // the event passes read and write more
  EXPECT_NE(simulation.profile_notes().find("bytes per particle and attempt"), std::string::npos);
}

// What the backend does not run is refused with the feature and its field, before anything runs;
// so are a device that does not exist and a scene larger than the device's memory.
TEST(DeviceIntegrator, RefusesWhatItCannotRun) {
  const auto refusal = [](const SceneSpec& spec) { return testing::refusal_of(spec); };
  // Implicit Euler in float32 (it runs in float64 only, on either backend), and imex.
  SceneSpec implicit = device_scene("paper-fig5", vulkan(Precision::float32));
  implicit.integrator.kind = IntegratorKind::implicit_euler;
  EXPECT_NE(refusal(implicit).find("float32 (precision) with implicit-euler"), std::string::npos);
  SceneSpec imex = device_scene("paper-fig5", vulkan(Precision::float32));
  imex.integrator.kind = IntegratorKind::imex;
  EXPECT_NE(refusal(imex).find("imex (integrator.method)"), std::string::npos);
  SceneSpec missing = device_scene("paper-fig5", BackendSettings{Backend::vulkan, 99, std::nullopt});
  EXPECT_NE(refusal(missing).find("no Vulkan device 99"), std::string::npos) << refusal(missing);
  // Self-collision runs there (on the host between the device's steps), switched on live too.
  Simulation simulation = make_simulation(device_scene("paper-fig5", vulkan(Precision::float32)));
  EXPECT_NO_THROW(simulation.set_self_collision(true));
  EXPECT_TRUE(simulation.model().collision.self);
  simulation.set_self_collision(false);
  // The laws of sheets that change run on the lattice path, not on the general one.
  {
    ClothModel model = paper_lattice(5, 5);
    model.limits.break_strain = 0.5;
    ForceOptions general;
    general.kernel = ForceKernel::general;
    EXPECT_THROW(gpu::DeviceIntegrator(model, IntegratorSettings{}, general, device0(Precision::float32)),
                 gpu::GpuError);
  }
  // A live edit the backend does not run is refused and changes nothing.
  IntegratorSettings imex_settings;
  imex_settings.kind = IntegratorKind::imex;
  EXPECT_THROW(simulation.set_integrator(imex_settings), BackendError);
  EXPECT_EQ(simulation.settings().integrator.kind, IntegratorKind::rkf45);
  EXPECT_TRUE(simulation.advance_to(0.05)) << simulation.failure()->message;
  // 20,000 x 20,000 particles: hundreds of GiB.
  try {
    check_backend_fits(lattice_counts(20000, 20000), 1, IntegratorSettings{}, vulkan(Precision::float32));
    ADD_FAILURE() << "a 20000 x 20000 sheet fits the device";
  } catch (const BackendError& error) {
    EXPECT_NE(std::string(error.what()).find("MiB of device memory"), std::string::npos) << error.what();
  }
  EXPECT_NO_THROW(check_backend_fits(lattice_counts(21, 21), 1, IntegratorSettings{}, vulkan(Precision::float32)));
}

// A step the error control cannot make small enough fails as on the CPU: with the time, the step
// and the particle, and the state of the last good step.
// A blow-up on the device is caught and diagnosed as on the CPU (issue 22): RK4 at 10 ms on
// paper-fig5, 23 times past its stable step, throws the sheet apart within the first frame. The
// host's blow-up check on the energy balance stops it at the same time and step as the CPU's run,
// with the same kind of message naming a particle, and keeps the last good state (finite), in both
// precisions.
TEST(DeviceIntegrator, ABlowUpIsDiagnosedAsOnTheCpu) {
  const auto blow_up = [](const BackendSettings& backend) {
    SceneSpec spec = device_scene("paper-fig5", backend);
    spec.integrator.kind = IntegratorKind::rk4;
    spec.integrator.time_step = 0.01;
    Simulation simulation = make_simulation(spec);
    bool failed = false;  // frame by frame, as a run writes them
    for (int frame = 1; frame <= 30 && !failed; ++frame) failed = !simulation.advance_to(frame / 60.0);
    EXPECT_TRUE(failed);
    for (const Vec3& x : simulation.state().position) EXPECT_TRUE(is_finite(x));
    return simulation.failure();
  };
  const std::optional<Diagnosis> cpu = blow_up(BackendSettings{});
  ASSERT_TRUE(cpu.has_value());
  for (Precision precision : {Precision::float64, Precision::float32}) {
    const std::optional<Diagnosis> device = blow_up(vulkan(precision));
    ASSERT_TRUE(device.has_value()) << to_string(precision);
    EXPECT_EQ(device->time, cpu->time) << to_string(precision);
    EXPECT_EQ(device->step, cpu->step) << to_string(precision);
    EXPECT_NE(device->message.find("the integration has blown up"), std::string::npos) << device->message;
    EXPECT_NE(device->element.find("particle"), std::string::npos) << device->element;
  }
  // Symplectic Euler at 0.2 s steps stretches a connector past 1000 times its rest length: the
  // state check names it. The device checks its state once per advance (a frame;
  // gpu/state_checks.h), and the host's check then names the connector, so the device's run stops
  // at that frame's end, later than the CPU's step by step.
  for (Precision precision : {Precision::float64, Precision::float32}) {
    SceneSpec spec = device_scene("paper-fig5", vulkan(precision));
    spec.integrator.kind = IntegratorKind::symplectic_euler;
    spec.integrator.time_step = 0.2;
    Simulation simulation = make_simulation(spec);
    bool failed = false;  // a frame a second, as `clothsim run --fps 1` writes them
    for (int frame = 1; frame <= 20 && !failed; ++frame) failed = !simulation.advance_to(frame);
    EXPECT_TRUE(failed) << to_string(precision);
    ASSERT_TRUE(simulation.failure().has_value());
    EXPECT_NE(simulation.failure()->message.find("exploded"), std::string::npos) << simulation.failure()->message;
    EXPECT_NE(simulation.failure()->element.find("connector"), std::string::npos) << simulation.failure()->element;
    for (const Vec3& x : simulation.state().position) EXPECT_TRUE(is_finite(x));
  }
}

TEST(DeviceIntegrator, AStepUnderflowIsDiagnosed) {
  SceneSpec spec = device_scene("paper-fig5", vulkan(Precision::float32));
  spec.integrator.relative_tolerance = 1e-14;
  spec.integrator.absolute_tolerance = 1e-14;
  spec.integrator.min_step = 1e-4;
  spec.integrator.time_step = 1e-4;
  Simulation simulation = make_simulation(spec);
  EXPECT_FALSE(simulation.advance_to(0.1));
  ASSERT_TRUE(simulation.failure().has_value());
  const std::string message = simulation.failure()->message;
  EXPECT_NE(message.find("step size underflow"), std::string::npos) << message;
  EXPECT_NE(message.find("particle"), std::string::npos) << message;
  for (const Vec3& x : simulation.state().position) EXPECT_TRUE(is_finite(x));
}

}  // namespace
}  // namespace clothsim
