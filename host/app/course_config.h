// The course's `.ini` configs (CS1230's ray project, SPEC §7): `ray CONFIG.ini` runs one as
// the course's `projects_ray CONFIG.ini` does.
//
//   [IO]       scene, output               paths relative to the working folder
//   [Canvas]   width, height
//   [Feature]  shadows, reflect, refract, texture, texture-filter, super-sample,
//              depthoffield, mipmapping    (true/false; texture-filter a name)
//              parallel, acceleration, post-process: accepted (ray is always parallel and
//              accelerated; it has no post-processing: one set true warns)
//   [Settings] maximum-recursive-depth, samples-per-pixel, super-sampler-pattern
//
// Each key is where the course's program reads it; one it does not read is a warning
// naming it (file:line), and is ignored as the course's program ignores it. A value that is
// not what its key takes is an error. What a key does, in ray's settings
// (render/settings_table.h):
//  - shadows, reflect, refract, texture, depthoffield: the switches of the same meaning
//    (--no-shadows, --no-reflections, --no-refraction, --no-textures, --no-dof). A key left
//    out is false, as the course's program reads it.
//  - super-sample false: one ray through each pixel's centre (--aa off), as the course's
//    program traces it. True: --samples samples-per-pixel, spread as the pattern says:
//    "adaptive" is --aa adaptive; "grid", "stratified" and "random" are --aa stratified
//    (one jittered sample in each cell of a grid: ray has no unjittered grid).
//  - texture-filter "nearest", "bilinear", "trilinear" (--texture-filter); with mipmapping
//    true, bilinear filtering is ray's mipmapped one, trilinear; trilinear without
//    mipmapping is an error, as in the course's program.
//  - maximum-recursive-depth: the depth; left out, 0, as the course's program reads it.
//  - width, height: the image's size; left out, ray's defaults.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "render/render_settings.h"

namespace ray {

struct CourseConfig {
    std::filesystem::path scene, output;  // as the config names them (relative to the working folder)
    RenderSettings settings;
    std::vector<std::string> warnings;  // complete ("config.ini:7: warning: ..."), for the caller to print
};

// Whether a command line's first positional is a config rather than a scene (by its
// extension, .ini in any case).
bool isCourseConfig(const std::filesystem::path& file);

// The config in `text`, read over `base` (the settings a key left out keeps); `file` names
// it in messages. With `strict`, a warning is an error. Throws InputError
// ("config.ini:12: error: ...; ...").
CourseConfig readCourseConfig(const std::string& text, const std::filesystem::path& file, const RenderSettings& base,
                              bool strict = false);

// The same from the file. Throws InputError.
CourseConfig loadCourseConfig(const std::filesystem::path& file, const RenderSettings& base, bool strict = false);

}  // namespace ray
