// The public Settings (include/ray/renderer.h) and RenderSettings, both ways, by walking
// the settings table (render/settings_table.h): each public field is named once, with its
// table name, in settings_conversion.cpp; ranges, choices and messages are the table's.
#pragma once

#include "ray/renderer.h"
#include "render/render_settings.h"

// Not part of libray.so's interface (only ray::api is: cmake/libray.map).
#pragma GCC visibility push(hidden)
namespace ray::api::detail {

// Throws InputError naming the first setting out of range ("error: width must be between
// 1 and 16384, not 0").
ray::RenderSettings toInternal(const Settings& settings);
Settings toPublic(const ray::RenderSettings& settings);

// The table's names without a public field, and public fields the table lacks: empty
// when the two agree (tests/test_settings_table.cpp).
std::vector<std::string> unmatchedSettingNames();

}  // namespace ray::api::detail
#pragma GCC visibility pop
