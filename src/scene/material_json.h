// The "material" object of scene files: a preset name, or an object of material fields
// (scene/parameters.h) read, checked and written back.
//
// Internal to src/scene: scene.cpp reads the document, applies the material (set_scene_material())
// and rechecks it in validate_scene(); the values are read through json_fields.h.
#pragma once

#include <string>

#include "model/material.h"
#include "scene/json_fields.h"

namespace clothsim::scene_json {

// The cross-field rule of a material object (the per-field ranges are checked while reading).
void check_material(const MaterialDef& material, const std::string& source, const std::string& field);

// A preset name, or an object of material fields (scene/parameters.h); fields not given keep
// MaterialDef's defaults (0, and never for the limits).
MaterialDef read_material(const json& value, const std::string& source, const std::string& field);

// A preset as its name; anything else as the full object, limits never written as null.
json material_to_json(const MaterialDef& material);

}  // namespace clothsim::scene_json
