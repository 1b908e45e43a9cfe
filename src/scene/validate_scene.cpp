// validate_scene() (validate_scene.h): each field against the registry, then the rules that
// involve several fields.
#include "scene/validate_scene.h"

#include <string>

#include "model/collider.h"
#include "scene/anchors_json.h"
#include "scene/colliders_json.h"
#include "scene/json_fields.h"
#include "scene/material_json.h"
#include "scene/parameters.h"
#include "scene/scene.h"

namespace clothsim {

using namespace scene_json;

namespace {

// Self-collision needs a thickness the lattice's own neighbours stay apart by
// (self_collision_thickness_limit, model/collider.h).
void check_self_collision_thickness(const SceneSpec& spec, const std::string& source) {
  if (!spec.collision.self) return;
  const double limit = self_collision_thickness_limit(spec.lattice.spacing);
  const double thickness = spec.collision.thickness;
  if (thickness < limit) return;
  fail(source, "collision.thickness",
       "must be below half the lattice spacing (" + format_number(limit) + " m) when collision.self is on, got " +
           format_number(thickness) + " (lower it with --thickness, or use fewer, larger lattice cells)");
}

}  // namespace

void validate_scene(const SceneSpec& spec, const std::string& source) {
  // A scene built in code, or by --set, must hold UTF-8 text, as a scene file does.
  read_text_string(spec.name, source, "name");
  read_text_string(spec.description, source, "description");
  for (const ScalarParameter& parameter : scalar_parameters()) {
    const double value = parameter.get(spec);
    if (!is_allowed(parameter.type, parameter.range, value)) {
      fail(source, std::string(parameter.key),
           "must be " + describe_allowed(parameter.type, parameter.range) + ", got " + format_number(value));
    }
  }
  for (const VectorParameter& parameter : vector_parameters()) {
    const Vec3 value = parameter.get(spec);
    for (int axis = 0; axis < 3; ++axis) {
      if (!parameter.component_range.contains(value[axis])) {
        fail(
            source, std::string(parameter.key) + "[" + std::to_string(axis) + "]",
            "must be a number in " + describe_range(parameter.component_range) + ", got " + format_number(value[axis]));
      }
    }
  }
  const LatticeDef& lattice = spec.lattice;
  if (static_cast<long long>(lattice.rows) * lattice.cols < 2) {
    fail(source, "lattice.rows",
         "lattice.rows x lattice.cols must be at least 2 particles, got " + std::to_string(lattice.rows) + " x " +
             std::to_string(lattice.cols));
  }
  if (yields_after_breaking(lattice.limits.yield_strain, lattice.limits.break_strain)) {
    fail(source, "springs.connector.yield_strain",
         "must be <= springs.connector.break_strain (" + format_number(lattice.limits.break_strain) + "), got " +
             format_number(lattice.limits.yield_strain) + ": a connector would break before it stretches for good");
  }
  if (spec.material) {
    for (const MaterialParameter& parameter : material_parameters()) {
      const double value = parameter.get(*spec.material);
      if (!is_allowed(parameter.type, parameter.range, value)) {
        fail(source, "material." + std::string(parameter.key),
             "must be " + describe_allowed(parameter.type, parameter.range) + ", got " + format_number(value));
      }
    }
    check_material(*spec.material, source, "material");
  }
  const IntegratorSettings integrator = scene_integrator(spec);
  if (integrator.min_step > integrator.max_step) {
    fail(source, "integrator.min_step",
         "must be <= integrator.max_step (" + format_number(integrator.max_step) + "), got " +
             format_number(integrator.min_step));
  }
  if (integrator.min_step > integrator.time_step) {
    fail(source, "integrator.min_step",
         "must be <= integrator.time_step (" + format_number(integrator.time_step) + "), got " +
             format_number(integrator.min_step));
  }
  // Anchors: inside the lattice, each particle at most once. A map over the anchors, not an array
  // over the particles: a 4096 x 4096 lattice would need 64 MiB to check two anchors.
  std::map<std::uint32_t, std::size_t> anchor_of_particle;
  for (std::size_t i = 0; i < spec.anchors.size(); ++i) {
    const AnchorSpec& anchor = spec.anchors[i];
    const std::string field = "anchors[" + std::to_string(i) + "]";
    validate_anchor(anchor, lattice, spec.output.duration, source, field);
    const std::uint32_t particle = lattice_index(lattice.cols, anchor.row, anchor.col);
    const auto [previous, inserted] = anchor_of_particle.emplace(particle, i);
    if (!inserted) {
      fail(source, field,
           "particle (row " + std::to_string(anchor.row) + ", col " + std::to_string(anchor.col) +
               ") is anchored twice (also by anchors[" + std::to_string(previous->second) + "])");
    }
  }
  for (std::size_t i = 0; i < spec.colliders.size(); ++i) {
    validate_collider(spec.colliders[i], source, "colliders[" + std::to_string(i) + "]");
  }
  check_self_collision_thickness(spec, source);
  const std::string unsupported = unsupported_by_backend(
      BackendFeatures{spec.integrator, spec.lattice.limits, !spec.colliders.empty(), spec.collision.self},
      spec.backend);
  if (!unsupported.empty()) fail(source, "backend", backend_refusal(unsupported, spec.backend));
}

}  // namespace clothsim
