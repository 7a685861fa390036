// The public API's checks of what its caller gives it that are not a scene's fields, each
// throwing InputError with a message that names the parameter as the caller (C++ or Python)
// knows it. Materials, lights, cameras and globals are the edit model's fields, checked by
// its table (edit/field_table.h) with the scenefile loader's rules.
#pragma once

#include "ray/renderer.h"
#include "ray/scene.h"
#include "core/atomic_file.h"
#include "scene/scene.h"

// Not part of libray.so's interface (only ray::api is: cmake/libray.map).
#pragma GCC visibility push(hidden)
namespace ray::api::detail {

// Numbers a scenefile could hold: finite (a translation, a scaling, a rotation's axis).
void checkFinite(const char* name, const Vec3& values);
void checkFinite(const char* name, double value);
// The settings table's ranges and choices (render/settings_table.h), as the command line's.
void checkSettings(const Settings& settings);
// The public WriteOptions as the writer's (core/atomic_file.h), its refusal naming the
// API's option.
ray::WriteOptions writeOptionsOf(const WriteOptions& options);
// A texture's size before its pixels are copied: the budget of a texture file
// (image/decode_limits.h), so that an array is held to what a file is.
void checkTextureSize(int64_t width, int64_t height);
// An image to save, before its pixels are copied: at most a render's largest, 16384 a side.
void checkImageToSaveSize(int64_t width, int64_t height, const std::string& file);

}  // namespace ray::api::detail
#pragma GCC visibility pop
