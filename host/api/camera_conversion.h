// The public Camera (include/ray/scene.h) to and from the internal one (scene/scene.h).
#pragma once

#include "ray/scene.h"
#include "scene/scene.h"

// Not part of libray.so's interface (only ray::api is: cmake/libray.map).
#pragma GCC visibility push(hidden)
namespace ray::api::detail {

inline ray::Vec3 toInternal(Vec3 v) { return {v.x, v.y, v.z}; }
inline Vec3 toPublic(ray::Vec3 v) { return {v.x, v.y, v.z}; }

inline ray::Camera toInternal(const Camera& c) {
    ray::Camera r;
    r.position = toInternal(c.position);
    r.look = toInternal(c.look);
    r.up = toInternal(c.up);
    r.heightAngleDegrees = c.heightAngleDegrees;
    r.aperture = c.aperture;
    r.focalLength = c.focalLength;
    return r;
}

inline Camera toPublic(const ray::Camera& c) {
    return {toPublic(c.position), toPublic(c.look), toPublic(c.up), c.heightAngleDegrees, c.aperture, c.focalLength};
}

}  // namespace ray::api::detail
#pragma GCC visibility pop
