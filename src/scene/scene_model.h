// From a scene to what the simulation runs: the model (lattice, anchors, limits, notches,
// colliders) and the initial state.
#pragma once

#include <vector>

#include "core/vec3.h"
#include "model/anchor.h"
#include "model/cloth_model.h"
#include "scene/scene.h"

namespace clothsim {

// Rest position of particle (row, col) in the flat lattice, m: ((col - (cols-1)/2) L, 0,
// (row - (rows-1)/2) L), the same value build_lattice() gives it.
Vec3 lattice_rest_position(const LatticeDef& lattice, int row, int col);
// The scene's anchors as the model takes them: particle index row*cols + col, and the path's
// origin set to the rest position where the scene did not give one.
std::vector<Anchor> resolve_anchors(const SceneSpec& spec);

ClothModel build_model(const SceneSpec& spec);
ClothState build_initial_state(const ClothModel& model, const SceneSpec& spec);

}  // namespace clothsim
