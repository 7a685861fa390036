// ray's public C++ API: load or build a scene, choose devices, render frames.
//
//   #include <ray/ray.h>
//   auto [scene, warnings] = ray::api::Scene::load("scene.xml");
//   ray::api::Renderer renderer(scene, "auto");
//   ray::api::Settings settings; settings.width = 640; settings.height = 480;
//   renderer.setSettings(settings);
//   std::vector<float> rgb = renderer.render();
//   ray::api::saveImage(rgb, 640, 480, "out.png");
//
// Link with the CMake package (find_package(ray) → ray::ray) or pkg-config (ray).
#pragma once

#include "ray/errors.h"
#include "ray/renderer.h"
#include "ray/scene.h"

namespace ray::api {

// The library's version, "major.minor.patch" (the CMake project's; the soname's is the major).
const char* version();

}  // namespace ray::api
