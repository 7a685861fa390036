// The public API's checks of what its caller gives it, each throwing InputError with a
// message that names the parameter as the caller (C++ or Python) knows it. Materials,
// lights and cameras keep the scenefile loader's rules (scene/parameter_rules.h), so that a
// scene built in code is refused exactly where the same scene written as XML would be.
#pragma once

#include "ray/renderer.h"
#include "ray/scene.h"
#include "scene/scene.h"

// Not part of libray.so's interface (only ray::api is: cmake/libray.map).
#pragma GCC visibility push(hidden)
namespace ray::api::detail {

void checkMaterial(const Material& material);
void checkLight(const Light& light);
void checkCamera(const ray::Camera& camera);
void checkGlobals(const Globals& globals);
// Numbers a scenefile could hold: finite (a translation, a scaling, a rotation's axis).
void checkFinite(const char* name, const Vec3& values);
void checkFinite(const char* name, double value);
// The settings table's ranges and choices (render/settings_table.h), as the command line's.
void checkSettings(const Settings& settings);

}  // namespace ray::api::detail
#pragma GCC visibility pop
