// The parts of a ClothModel that change after it is built, transferred through a StateArchive
// (core/state_archive.h) for checkpoints (io/checkpoint.h).
//
// What changes, and so what is saved: everything model/model_edits.h writes. Tearing, permanent
// stretching and creasing change the per-spring state (intact or broken, break time, rest length
// and angle, hardened yield limits); anchors arrive, stop and let go (the anchor list and each
// particle's anchor and inverse mass); live edits change stiffness, damping, mass, the
// environment, the limits, self-collision and the colliders' positions and paths.
//
// What does not change, and is rebuilt from the scene instead: the topology (which particles each
// spring joins), the rest positions, the original rest values, the force gather table, mesh
// colliders' triangles. A loaded checkpoint must therefore be applied to the model built from the
// same scene; the archive checks every array's length, and the particle, connector, radial spring
// and collider counts must match.
#pragma once

#include "core/state_archive.h"
#include "model/cloth_model.h"

namespace clothsim {

// Saves or restores (archive.loading()) the changing parts of `model`. Restoring throws
// std::runtime_error naming the field when the archive does not fit the model.
void transfer_model_changes(StateArchive& archive, ClothModel& model);

}  // namespace clothsim
