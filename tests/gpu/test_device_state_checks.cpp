// A frame's energies and state checks on the device (gpu/state_checks.h, issue 22 item 3), on
// the machine's Vulkan device (lavapipe on CI): the device's sums against the host's
// compute_energy of the same state, and the checks' failures against Simulation::check_state's.
//
// In float64 the device and the host sum the same formulas of the same numbers: they agree to
// the rounding of the sums' order, 1e-12 of the energies' scale. In float32 the device's masses
// and spring parameters are rounded to float (its forces use those too), and its sums are the
// host's for a model with its parameters rounded so, and its radial springs' rest angles as the
// float forces take them, to the same 1e-12; against the model's own parameters they differ by
// far more (the rest angle pi/2 is not a float), which the test states as well, so that it knows
// whose sums it compares.
#include "integrators/integrator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "device_models.h"
#include "forces/element.h"
#include "forces/forces.h"
#include "implicit_scenes.h"
#include "model/cloth_model.h"
#include "model/model_edits.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene/scene_simulation.h"
#include "scene/validate_scene.h"
#include "sim/backend.h"
#include "sim/simulation.h"

namespace clothsim {
namespace {

constexpr double kExplosionStretch = SimulationSettings{}.explosion_stretch;

using testing::cotton;
using testing::paper_lattice;
using testing::vulkan;

// The model as a float32 device holds it: masses and spring parameters rounded to float.
ClothModel rounded_to_float(ClothModel model) {
  for (std::vector<double>* values : {&model.particle_mass, &model.connector_rest_length, &model.connector_stiffness,
                                      &model.connector_original_length, &model.radial_rest_angle,
                                      &model.radial_stiffness}) {
    for (double& value : *values) value = static_cast<double>(static_cast<float>(value));
  }
  return model;
}

// The energies of the float32 device's dynamics, on the host: compute_energy of the model rounded
// to float, with each radial spring's rest angle as the float forces take it (state_checks.glsl,
// acting_rest_angle): past pi/2, pi less the rounded angle's distance from pi in float, so that
// pi rounded to float acts as pi.
EnergyReport float32_energy(const ClothModel& model, const ClothState& state) {
  const ClothModel rounded = rounded_to_float(model);
  EnergyReport energy = compute_energy(rounded, state, kAllForceTerms, 1);
  energy.radial_adjacent = 0.0;
  energy.radial_opposite = 0.0;
  for (std::size_t r = 0; r < rounded.radial_count(); ++r) {
    if (rounded.radial_live[r] == 0) continue;
    const auto [a, b, c] = rounded.radial_particles[r];
    const Vec3& xa = state.position[a];
    const Vec3& xb = state.position[b];
    const Vec3& xc = state.position[c];
    const double angle = element::radial_angle(xa, xb, xc);
    const auto rest = static_cast<float>(rounded.radial_rest_angle[r]);
    const float from_straight = static_cast<float>(element::kStraightAngle) - rest;  // in float
    const double acting =
        angle <= 0.5 * element::kStraightAngle ? rest : element::kStraightAngle - static_cast<double>(from_straight);
    const std::array<double, 2> fade = radial_fade_lengths(rounded, r);
    const double d = angle - acting;
    const double e = element::arm_fade(norm(xb - xa), fade[0]).value * element::arm_fade(norm(xc - xa), fade[1]).value *
                     (0.5 * rounded.radial_stiffness[r] * d * d);
    (rounded.radial_kind[r] == RadialKind::adjacent ? energy.radial_adjacent : energy.radial_opposite) += e;
  }
  return energy;
}

// The scale the sums are compared at: the terms' magnitudes added.
double scale_of(const EnergyReport& e) {
  return std::abs(e.kinetic) + std::abs(e.gravitational) + std::abs(e.connector) + std::abs(e.radial_adjacent) +
         std::abs(e.radial_opposite);
}

double largest_difference(const EnergyReport& a, const EnergyReport& b) {
  return std::max({std::abs(a.kinetic - b.kinetic), std::abs(a.gravitational - b.gravitational),
                   std::abs(a.connector - b.connector), std::abs(a.radial_adjacent - b.radial_adjacent),
                   std::abs(a.radial_opposite - b.radial_opposite)});
}

// Each term of the device's sums against the host's of `model` (rounded to float for float32).
void expect_host_sums(const EnergyReport& device, const ClothModel& model, const ClothState& state,
                      Precision precision, const char* what) {
  const EnergyReport exact = compute_energy(model, state, kAllForceTerms, 1);
  const EnergyReport host = precision == Precision::float64 ? exact : float32_energy(model, state);
  const double scale = std::max(1e-6, scale_of(host));  // a microjoule at least: a sheet at rest has none
  const double difference = largest_difference(device, host);
  std::printf("%s, %s: energies %.9g J (connector %.6g, radial %.6g + %.6g, kinetic %.6g, gravitational %.6g); "
              "the host's differ by %.3g J, with the unrounded parameters by %.3g J\n",
              what, to_string(precision), device.total(), device.connector, device.radial_adjacent,
              device.radial_opposite, device.kinetic, device.gravitational, difference,
              largest_difference(device, exact));
  EXPECT_LT(difference, 1e-12 * scale) << what << ", " << to_string(precision);
  if (precision == Precision::float32) {
    EXPECT_GT(largest_difference(device, exact), 1e3 * difference)
        << what << ": the float32 sums are the device's, with its rounded parameters";
  }
}

// Each device integrator and path: the explicit methods on the lattice path and on the general
// path (the element arrays), in both precisions, and implicit Euler (float64, the general path).
struct Checked {
  const char* name;
  IntegratorKind kind;
  ForceKernel kernel;
  Precision precision;
};
constexpr Checked kChecked[] = {
    {"lattice path", IntegratorKind::rkf45, ForceKernel::automatic, Precision::float64},
    {"lattice path", IntegratorKind::rkf45, ForceKernel::automatic, Precision::float32},
    {"general path", IntegratorKind::rkf45, ForceKernel::general, Precision::float64},
    {"general path", IntegratorKind::rkf45, ForceKernel::general, Precision::float32},
    {"implicit Euler", IntegratorKind::implicit_euler, ForceKernel::automatic, Precision::float64},
};

std::unique_ptr<Integrator> device_integrator(const ClothModel& model, const Checked& checked) {
  IntegratorSettings settings;
  settings.kind = checked.kind;
  if (checked.kind == IntegratorKind::implicit_euler) settings.time_step = 1.0 / 60.0;
  ForceOptions options;
  options.kernel = checked.kernel;
  return make_backend_integrator(model, settings, options,
                                 BackendSettings{Backend::vulkan, 0, request(checked.precision)});
}

// A lattice of 23 x 17 (391 particles: a workgroup and a part, and a shape that is not square),
// swinging from a corner after half a second, checked at rest and after the host moved it.
TEST(DeviceStateChecks, EnergiesAreTheHostsSums) {
  for (const Checked& checked : kChecked) {
    ClothModel model = paper_lattice(23, 17);
    AnchorPath corner;
    corner.origin = model.particle_rest_position[0];
    set_anchor(model, 0, corner);
    const std::unique_ptr<Integrator> integrator = device_integrator(model, checked);
    ClothState state;
    state.position = model.particle_rest_position;
    state.velocity.assign(model.particle_count(), Vec3{});
    const Precision precision = checked.precision;
    const std::string at_rest = std::string(checked.name) + ", at rest";
    std::optional<StateChecks> checks = integrator->check_state(state, kExplosionStretch);
    ASSERT_TRUE(checks.has_value()) << "lavapipe has shaderFloat64";
    EXPECT_FALSE(checks->failed);
    expect_host_sums(checks->energy, model, state, precision, at_rest.c_str());

    ASSERT_EQ(integrator->advance(state, 0.5).status, StepStatus::ok);
    checks = integrator->check_state(state, kExplosionStretch);
    ASSERT_TRUE(checks.has_value());
    EXPECT_FALSE(checks->failed);
    const std::string later = std::string(checked.name) + ", after 0.5 s";
    expect_host_sums(checks->energy, model, state, precision, later.c_str());

    // A state the host changed since the advance goes up before the sums.
    state.position[200].y += 0.25;
    state.velocity[17] = {1.0, -2.0, 0.5};
    checks = integrator->check_state(state, kExplosionStretch);
    ASSERT_TRUE(checks.has_value());
    const std::string moved = std::string(checked.name) + ", moved by the host";
    expect_host_sums(checks->energy, model, state, precision, moved.c_str());
  }
}

// The checks fail where Simulation::check_state fails: a non-finite position or velocity, a
// live connector longer than the limit; a broken connector may stretch without limit.
TEST(DeviceStateChecks, FailuresAreTheHostsChecks) {
  for (const Checked& checked : kChecked) {
    ClothModel model = paper_lattice(9, 30);
    const std::unique_ptr<Integrator> integrator = device_integrator(model, checked);
    const std::string what = std::string(checked.name) + ", " + to_string(checked.precision);
    ClothState state;
    state.position = model.particle_rest_position;
    state.velocity.assign(model.particle_count(), Vec3{});
    const auto failed = [&](const ClothState& s, double limit = kExplosionStretch) {
      const std::optional<StateChecks> checks = integrator->check_state(s, limit);
      EXPECT_TRUE(checks.has_value());
      return checks.has_value() && checks->failed;
    };
    EXPECT_FALSE(failed(state)) << what;
    ClothState bad = state;
    bad.velocity[130].z = std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(failed(bad)) << what << ": a NaN velocity";
    bad = state;
    bad.position[269].x = std::numeric_limits<double>::infinity();
    EXPECT_TRUE(failed(bad)) << what << ": an infinite position, the last particle";
    // Particle 100 is 2,000 m away: its four connectors are 2,000 times their rest length.
    bad = state;
    bad.position[100].y += 2000.0;
    EXPECT_TRUE(failed(bad)) << what << ": an exploded connector";
    EXPECT_FALSE(failed(bad, 3000.0)) << what << ": under a limit of 3,000";
    // Torn off (every connector to it broken), it may be anywhere.
    for (std::size_t e = 0; e < model.connector_count(); ++e) {
      const auto [a, b] = model.connector_particles[e];
      if (a == 100 || b == 100) break_connector(model, static_cast<std::uint32_t>(e), 0.0);
    }
    EXPECT_FALSE(failed(bad)) << what << ": a torn-off particle";
    std::printf("%s: the failures found\n", what.c_str());
  }
}

// Through the Simulation: each frame's energies, which energy.csv and the energy balance read,
// are the device's sums of its state, on the paper's scene and on a sheet that tears, yields and
// creases on the device (whose changed parameters the model then holds as the device has them).
TEST(DeviceStateChecks, TheSimulationsEnergiesAreTheDevicesSums) {
  SceneSpec tearing = scene_from_paper_args("11,11,1,4,1,1400,200,80,5,1", "test");
  set_scene_field(tearing, "anchors",
                  R"([{"row": 0, "col": 0}, {"row": 0, "col": 10},
                      {"row": 10, "col": 0, "path": {"type": "keyframes", "keys": [[0, 0, 0, 0], [0.6, 0, -3, 0]]}},
                      {"row": 10, "col": 10, "path": {"type": "keyframes", "keys": [[0, 0, 0, 0], [0.6, 0, -3, 0]]}}])",
                  "test");
  set_scene_field(tearing, "springs.connector.break_strain", "0.06", "test");
  set_scene_field(tearing, "springs.connector.yield_strain", "0.02", "test");
  set_scene_field(tearing, "springs.adjacent.yield_angle_deg", "2", "test");
  validate_scene(tearing, "test");
  // Implicit Euler at the frame step, on the general path.
  const SceneSpec drape = cotton(24, testing::kVulkan, true);
  for (Precision precision : {Precision::float64, Precision::float32}) {
    for (SceneSpec spec : {builtin_scene("paper-fig5"), tearing, drape}) {
      if (spec.integrator.kind == IntegratorKind::implicit_euler && precision == Precision::float32) continue;
      spec.backend = vulkan(precision);
      Simulation simulation = make_simulation(spec);
      for (int frame = 1; frame <= 24; ++frame) {
        ASSERT_TRUE(simulation.advance_to(frame / 60.0)) << simulation.failure()->message;
      }
      expect_host_sums(simulation.energy(), simulation.model(), simulation.state(), precision, spec.name.c_str());
      if (spec.name == tearing.name) {
        EXPECT_GT(simulation.event_totals().breaks, 0u) << "the sheet tears";
        EXPECT_GT(simulation.event_totals().yields, 0u) << "and yields";
      }
    }
  }
}

}  // namespace
}  // namespace clothsim
