#include "model/model_state.h"

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace clothsim {
namespace {

// An anchor path's fields; every kind's, so that a path keeps all it had.
void transfer_path(StateArchive& archive, const std::string& name, AnchorPath& path) {
  archive.value(name + ".kind", path.kind);
  archive.value(name + ".origin", path.origin);
  archive.value(name + ".velocity", path.velocity);
  archive.value(name + ".amplitude", path.amplitude);
  archive.value(name + ".frequency", path.frequency);
  archive.value(name + ".phase", path.phase);
  archive.value(name + ".start_time", path.start_time);
  archive.value(name + ".end_time", path.end_time);
  std::vector<double> key_time;
  std::vector<Vec3> key_offset;
  if (!archive.loading()) {
    for (const AnchorKey& key : path.keys) {
      key_time.push_back(key.time);
      key_offset.push_back(key.offset);
    }
  }
  archive.vector(name + ".key_time", key_time);
  archive.vector(name + ".key_offset", key_offset);
  if (archive.loading()) {
    if (key_time.size() != key_offset.size()) {
      throw std::runtime_error("field '" + name + ".key_offset' has " + std::to_string(key_offset.size()) +
                               " values for " + std::to_string(key_time.size()) + " key times");
    }
    path.keys.clear();
    for (std::size_t k = 0; k < key_time.size(); ++k) path.keys.push_back(AnchorKey{key_time[k], key_offset[k]});
  }
}

void transfer_anchors(StateArchive& archive, ClothModel& model) {
  std::uint64_t count = model.anchors.size();
  archive.value("anchors.size", count);
  if (archive.loading()) {
    // An anchor holds a particle, so there are never more anchors than particles.
    if (count > model.particle_count()) {
      throw std::runtime_error("field 'anchors.size' is " + std::to_string(count) + ", more than the " +
                               std::to_string(model.particle_count()) + " particles");
    }
    model.anchors.assign(static_cast<std::size_t>(count), Anchor{});
  }
  for (std::size_t i = 0; i < model.anchors.size(); ++i) {
    Anchor& anchor = model.anchors[i];
    const std::string name = "anchors." + std::to_string(i);
    archive.value(name + ".particle", anchor.particle);
    archive.value(name + ".release_time", anchor.release_time);
    transfer_path(archive, name + ".path", anchor.path);
    if (archive.loading() && anchor.particle >= model.particle_count()) {
      throw std::runtime_error("field '" + name + ".particle' is " + std::to_string(anchor.particle) +
                               ", not a particle of the " + std::to_string(model.particle_count()));
    }
  }
}

void transfer_colliders(StateArchive& archive, ClothModel& model) {
  std::uint64_t count = model.colliders.size();
  archive.value("colliders.size", count);
  if (archive.loading() && count != model.colliders.size()) {
    throw std::runtime_error("field 'colliders.size' is " + std::to_string(count) + " but the scene has " +
                             std::to_string(model.colliders.size()) + " colliders");
  }
  for (std::size_t i = 0; i < model.colliders.size(); ++i) {
    Collider& collider = model.colliders[i];
    const std::string name = "colliders." + std::to_string(i);
    archive.value(name + ".point", collider.point);
    archive.value(name + ".normal", collider.normal);
    archive.value(name + ".center", collider.center);
    archive.value(name + ".radius", collider.radius);
    archive.value(name + ".half_extents", collider.half_extents);
    archive.value(name + ".a", collider.a);
    archive.value(name + ".b", collider.b);
    archive.value(name + ".friction", collider.friction);
    transfer_path(archive, name + ".path", collider.path);
  }
}

}  // namespace

void transfer_model_changes(StateArchive& archive, ClothModel& model) {
  archive.value("model.revision", model.revision);

  archive.array("particle_mass", model.particle_mass);
  archive.array("particle_inverse_mass", model.particle_inverse_mass);
  archive.array("particle_anchor", model.particle_anchor);

  archive.array("connector_rest_length", model.connector_rest_length);
  archive.array("connector_stiffness", model.connector_stiffness);
  archive.array("connector_damping", model.connector_damping);
  archive.array("connector_live", model.connector_live);
  archive.array("connector_break_time", model.connector_break_time);
  archive.array("connector_break_strain", model.connector_break_strain);
  archive.array("connector_yield_strain", model.connector_yield_strain);
  archive.value("broken_connector_count", model.broken_connector_count);

  archive.array("radial_rest_angle", model.radial_rest_angle);
  archive.array("radial_stiffness", model.radial_stiffness);
  archive.array("radial_damping", model.radial_damping);
  archive.array("radial_live", model.radial_live);
  archive.array("radial_yield_angle", model.radial_yield_angle);

  SpringLimits& limits = model.limits;
  archive.value("limits.break_strain", limits.break_strain);
  archive.value("limits.break_strain_variation", limits.break_strain_variation);
  archive.value("limits.variation_seed", limits.variation_seed);
  archive.value("limits.yield_strain", limits.yield_strain);
  archive.value("limits.hardening", limits.hardening);
  archive.value("limits.adjacent_yield_angle", limits.adjacent_yield_angle);
  archive.value("limits.opposite_yield_angle", limits.opposite_yield_angle);

  transfer_anchors(archive, model);
  archive.value("environment.gravity", model.environment.gravity);
  archive.value("environment.air_drag", model.environment.air_drag);
  transfer_colliders(archive, model);
  archive.value("collision.thickness", model.collision.thickness);
  archive.value("collision.self", model.collision.self);
  archive.value("collision.friction", model.collision.friction);

  // The anchor list and each particle's anchor index must agree, or the integrators would
  // integrate a held particle (or hold a free one).
  if (archive.loading()) {
    std::size_t anchored = 0;
    for (std::size_t p = 0; p < model.particle_count(); ++p) {
      const std::int32_t a = model.particle_anchor[p];
      if (a < 0) continue;
      ++anchored;
      if (static_cast<std::size_t>(a) >= model.anchors.size() ||
          model.anchors[static_cast<std::size_t>(a)].particle != p) {
        throw std::runtime_error("field 'particle_anchor' names anchor " + std::to_string(a) + " for particle " +
                                 std::to_string(p) + ", which that anchor does not hold");
      }
    }
    if (anchored != model.anchors.size()) {
      throw std::runtime_error("fields 'particle_anchor' and 'anchors' disagree: " + std::to_string(anchored) +
                               " anchored particles, " + std::to_string(model.anchors.size()) + " anchors");
    }
  }
}

}  // namespace clothsim
