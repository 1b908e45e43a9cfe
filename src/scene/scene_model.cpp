// From a scene to its model and initial state (scene_model.h).
#include "scene/scene_model.h"

#include <cstdint>
#include <vector>

#include "model/initial_conditions.h"
#include "model/lattice_cuts.h"
#include "model/model_edits.h"
#include "model/spring_limits.h"
#include "scene/scene.h"

namespace clothsim {

Vec3 lattice_rest_position(const LatticeDef& lattice, int row, int col) {
  // The same expression as build_lattice(), so that an anchor at its default origin sits exactly
  // on its particle's rest position.
  return {(col - (lattice.cols - 1) / 2.0) * lattice.spacing, 0.0, (row - (lattice.rows - 1) / 2.0) * lattice.spacing};
}

std::vector<Anchor> resolve_anchors(const SceneSpec& spec) {
  std::vector<Anchor> anchors;
  anchors.reserve(spec.anchors.size());
  for (const AnchorSpec& anchor : spec.anchors) {
    AnchorPath path = anchor.path;
    if (!anchor.origin_given) path.origin = lattice_rest_position(spec.lattice, anchor.row, anchor.col);
    anchors.push_back(Anchor{lattice_index(spec.lattice.cols, anchor.row, anchor.col), path, anchor.release_time});
  }
  return anchors;
}

ClothModel build_model(const SceneSpec& spec) {
  const std::vector<Anchor> anchors = resolve_anchors(spec);
  ClothModel model = build_lattice(spec.lattice, spec.environment, anchors, "scene '" + spec.name + "'");
  // The scene's seed varies the break strains, as it varies the initial perturbation.
  SpringLimits limits = spec.lattice.limits;
  limits.variation_seed = spec.initial.seed;
  apply_spring_limits(model, limits);
  // Notches: broken before the run starts (t = 0), so they store no energy and book no work.
  for (const CutSpec& cut : spec.cuts) {
    for (std::uint32_t connector : connectors_crossed_in_lattice(model, cut.from, cut.to)) {
      break_connector(model, connector, 0.0);
    }
  }
  for (const ColliderSpec& collider : spec.colliders) model.colliders.push_back(collider.collider);
  model.collision = spec.collision;
  return model;
}

ClothState build_initial_state(const ClothModel& model, const SceneSpec& spec) {
  ClothState state = make_rest_state(model);
  apply_initial_conditions(model, spec.initial, state);
  return state;
}

}  // namespace clothsim
