// The checks of a whole scene, after every field was read: each field again against the
// parameter registry (so that scenes built in code get the same protection as files), then the
// rules that involve several fields.
#pragma once

#include <string>

#include "scene/scene.h"

namespace clothsim {

// Checks cross-field constraints (anchors inside the lattice, ...). Throws InputError.
void validate_scene(const SceneSpec& spec, const std::string& source);

}  // namespace clothsim
