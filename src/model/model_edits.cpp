#include "model/model_edits.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/assert.h"

namespace clothsim {
namespace {

// Moves a collider's shape (its position at t = 0) by `offset`.
void translate_shape(Collider& collider, const Vec3& offset) {
  CLOTHSIM_ASSERT(collider.shape != ColliderShape::mesh, "mesh colliders are not moved by hand");
  collider.point += offset;
  collider.center += offset;
  collider.a += offset;
  collider.b += offset;
}

}  // namespace

bool break_connector(ClothModel& model, std::uint32_t connector, double time) {
  CLOTHSIM_ASSERT(connector < model.connector_count(), "broken connector is in the model");
  if (model.connector_live[connector] == 0) return false;
  model.connector_live[connector] = 0;
  model.connector_break_time[connector] = time;
  for (std::uint32_t k = model.connector_radial_offset[connector]; k < model.connector_radial_offset[connector + 1];
       ++k) {
    model.radial_live[model.radial_of_connector[k]] = 0;
  }
  ++model.broken_connector_count;
  ++model.revision;
  return true;
}

void set_connector_rest_length(ClothModel& model, std::uint32_t connector, double rest_length) {
  CLOTHSIM_ASSERT(connector < model.connector_count(), "connector is in the model");
  CLOTHSIM_ASSERT(rest_length > 0.0 && std::isfinite(rest_length), "rest length is positive");
  model.connector_rest_length[connector] = rest_length;
  ++model.revision;
}

void set_connector_yield_strain(ClothModel& model, std::uint32_t connector, double yield_strain) {
  CLOTHSIM_ASSERT(connector < model.connector_count(), "connector is in the model");
  CLOTHSIM_ASSERT(yield_strain > 0.0, "yield strain is positive");
  model.connector_yield_strain[connector] = yield_strain;
  ++model.revision;
}

void set_radial_rest_angle(ClothModel& model, std::uint32_t radial, double rest_angle) {
  CLOTHSIM_ASSERT(radial < model.radial_count(), "radial spring is in the model");
  CLOTHSIM_ASSERT(rest_angle >= 0.0 && rest_angle <= std::numbers::pi, "rest angle is in [0, pi]");
  model.radial_rest_angle[radial] = rest_angle;
  ++model.revision;
}

void set_spring_family(ClothModel& model, SpringFamily family, const SpringParameters& parameters) {
  CLOTHSIM_ASSERT(parameters.stiffness >= 0.0 && parameters.damping >= 0.0, "spring constants are not negative");
  if (family == SpringFamily::connector) {
    std::fill(model.connector_stiffness.begin(), model.connector_stiffness.end(), parameters.stiffness);
    std::fill(model.connector_damping.begin(), model.connector_damping.end(), parameters.damping);
    ++model.revision;
    return;
  }
  const RadialKind kind = family == SpringFamily::adjacent ? RadialKind::adjacent : RadialKind::opposite;
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    if (model.radial_kind[r] != kind) continue;
    model.radial_stiffness[r] = parameters.stiffness;
    model.radial_damping[r] = parameters.damping;
  }
  ++model.revision;
}

void set_particle_mass(ClothModel& model, double mass) {
  CLOTHSIM_ASSERT(mass > 0.0 && std::isfinite(mass), "particle mass is positive");
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    model.particle_mass[p] = mass;
    model.particle_inverse_mass[p] = model.is_anchored(p) ? 0.0 : 1.0 / mass;
  }
  ++model.revision;
}

void set_anchor(ClothModel& model, std::uint32_t particle, const AnchorPath& path) {
  CLOTHSIM_ASSERT(particle < model.particle_count(), "anchored particle is in the lattice");
  if (model.is_anchored(particle)) {
    model.anchors[static_cast<std::size_t>(model.particle_anchor[particle])].path = path;
    ++model.revision;
    return;
  }
  model.particle_anchor[particle] = static_cast<std::int32_t>(model.anchors.size());
  model.particle_inverse_mass[particle] = 0.0;
  model.anchors.push_back(Anchor{particle, path});
  ++model.revision;
}

bool remove_anchor(ClothModel& model, std::uint32_t particle) {
  CLOTHSIM_ASSERT(particle < model.particle_count(), "freed particle is in the lattice");
  if (!model.is_anchored(particle)) return false;
  const auto index = static_cast<std::size_t>(model.particle_anchor[particle]);
  const Anchor last = model.anchors.back();
  model.anchors[index] = last;
  model.particle_anchor[last.particle] = static_cast<std::int32_t>(index);
  model.anchors.pop_back();
  model.particle_anchor[particle] = -1;
  model.particle_inverse_mass[particle] = 1.0 / model.particle_mass[particle];
  ++model.revision;
  return true;
}

void set_environment(ClothModel& model, const Environment& environment) {
  CLOTHSIM_ASSERT(is_finite(environment.gravity) && environment.air_drag >= 0.0, "environment is valid");
  model.environment = environment;
  ++model.revision;
}

void set_self_collision(ClothModel& model, bool on) {
  model.collision.self = on;
  ++model.revision;
}

std::size_t add_collider(ClothModel& model, const Collider& collider) {
  model.colliders.push_back(collider);
  ++model.revision;
  return model.colliders.size() - 1;
}

void drive_collider(ClothModel& model, std::size_t collider, const Vec3& displacement, double now,
                    double arrival_time) {
  CLOTHSIM_ASSERT(collider < model.colliders.size(), "driven collider is in the model");
  CLOTHSIM_ASSERT(arrival_time > now && now >= 0.0, "a driven collider arrives after the current time");
  Collider& moved = model.colliders[collider];
  AnchorPath path;
  path.kind = AnchorPathKind::driven;
  path.start_time = now;
  path.end_time = arrival_time;
  path.velocity = displacement / (arrival_time - now);
  // A collider at time t is its t = 0 shape translated by path(t) - path(0), which for this path
  // is min(t, arrival_time) * velocity: rebase the shape so that it is where it is now at `now`.
  translate_shape(moved, collider_offset(moved, now) - now * path.velocity);
  moved.path = path;
  ++model.revision;
}

void place_collider(ClothModel& model, std::size_t collider, const Vec3& displacement, double now) {
  CLOTHSIM_ASSERT(collider < model.colliders.size(), "placed collider is in the model");
  Collider& moved = model.colliders[collider];
  translate_shape(moved, collider_offset(moved, now) + displacement);
  moved.path = AnchorPath{};
  ++model.revision;
}

}  // namespace clothsim
