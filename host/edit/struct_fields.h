// A whole material, light, camera or globals as the field inputs of an edit, read off the
// field table (field_table.h): how the C++ API's structs (include/ray/scene.h) become the
// one edit model's SetFields, with no list of their fields of its own.
#pragma once

#include <vector>

#include "edit/field_table.h"
#include "scene/scene.h"

namespace ray::edit {

// Every camera field, and every globals field.
std::vector<FieldInput> cameraFields(const Camera& camera);
std::vector<FieldInput> globalsFields(const GlobalCoefficients& globals);
// The light's type, then every field its type uses (with `all`, every field of a light:
// a struct's fields its type does not use are checked all the same).
std::vector<FieldInput> lightFields(const Light& light, bool all = false);
// The material's colors and numbers; with `textures`, its texture and bump map (a handle,
// or none) and their repeats.
std::vector<FieldInput> materialFields(const Material& material, bool textures);

}  // namespace ray::edit
