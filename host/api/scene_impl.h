// What a public ray::api::Scene holds: the internal flattened Scene both renderers take.
#pragma once

#include "ray/scene.h"
#include "scene/scene.h"

namespace ray::api {

struct Scene::Impl {
    ray::Scene scene;
};

}  // namespace ray::api
