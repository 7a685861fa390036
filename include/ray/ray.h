/// \file
/// ray's public C++ API: load or build a scene, choose devices, render frames.
///
/// \code
///   #include <ray/ray.h>
///   auto [scene, warnings] = ray::api::Scene::load("scene.xml");
///   ray::api::Renderer renderer(scene, "auto");
///   ray::api::Settings settings; settings.width = 640; settings.height = 480;
///   renderer.setSettings(settings);
///   std::vector<float> rgb = renderer.render();
///   ray::api::saveImage(rgb, 640, 480, "out.png");
/// \endcode
///
/// Link with the CMake package (find_package(ray) → ray::ray) or pkg-config (ray).

/// \mainpage
/// The C++ API of ray, a ray tracer for CS123 scenefiles: `<ray/ray.h>` includes every
/// header. A ray::api::Scene is loaded from a scenefile or built in code; a
/// ray::api::Renderer renders it on a device selection, frame after frame, with
/// ray::api::Settings; ray::api::saveImage writes the result. Errors are
/// ray::api::InputError and ray::api::DeviceError. docs/embedding.md in the repository
/// shows a whole program and the Python module over the same API.
#pragma once

#include "ray/errors.h"
#include "ray/renderer.h"
#include "ray/scene.h"

/// ray's public C++ API (everything else in libray.so is internal and not exported).
namespace ray::api {

/// The library's version, "major.minor.patch" (the CMake project's; the soname's is the major).
const char* version();

}  // namespace ray::api
