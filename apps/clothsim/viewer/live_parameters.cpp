#include "viewer/live_parameters.h"

#include <algorithm>
#include <array>

namespace clothsim::viewer {
namespace {

constexpr std::array<std::string_view, 18> kLiveKeys = {
    "springs.connector.stiffness", "springs.connector.damping",     "springs.adjacent.stiffness",
    "springs.adjacent.damping",    "springs.opposite.stiffness",    "springs.opposite.damping",
    "environment.gravity",         "environment.air_drag",          "lattice.particle_mass",
    "integrator.method",           "integrator.relative_tolerance", "integrator.absolute_tolerance",
    "integrator.time_step",        "integrator.min_step",           "integrator.max_step",
    "integrator.safety",           "integrator.max_growth",         "integrator.max_shrink",
};

bool same(const SpringParameters& a, const SpringParameters& b) {
  return a.stiffness == b.stiffness && a.damping == b.damping;
}

bool same(const IntegratorSettings& a, const IntegratorSettings& b) {
  return a.kind == b.kind && a.relative_tolerance == b.relative_tolerance &&
         a.absolute_tolerance == b.absolute_tolerance && a.time_step == b.time_step && a.min_step == b.min_step &&
         a.max_step == b.max_step && a.safety == b.safety && a.max_growth == b.max_growth &&
         a.max_shrink == b.max_shrink;
}

}  // namespace

std::span<const std::string_view> live_parameter_keys() { return kLiveKeys; }

bool is_live_parameter(std::string_view key) {
  return std::find(kLiveKeys.begin(), kLiveKeys.end(), key) != kLiveKeys.end();
}

std::string live_parameter_list() {
  std::string text;
  for (std::string_view key : kLiveKeys) text += (text.empty() ? "" : ", ") + std::string(key);
  return text;
}

void apply_live_parameters(const SceneSpec& current, const SceneSpec& edited, Simulation& simulation) {
  const LatticeDef& was = current.lattice;
  const LatticeDef& now = edited.lattice;
  if (!same(was.connector, now.connector)) simulation.set_spring_parameters(SpringFamily::connector, now.connector);
  if (!same(was.adjacent, now.adjacent)) simulation.set_spring_parameters(SpringFamily::adjacent, now.adjacent);
  if (!same(was.opposite, now.opposite)) simulation.set_spring_parameters(SpringFamily::opposite, now.opposite);
  if (was.particle_mass != now.particle_mass) simulation.set_particle_mass(now.particle_mass);
  if (!(current.environment.gravity == edited.environment.gravity) ||
      current.environment.air_drag != edited.environment.air_drag) {
    simulation.set_environment(edited.environment);
  }
  if (!same(current.integrator, edited.integrator)) simulation.set_integrator(edited.integrator);
}

}  // namespace clothsim::viewer
