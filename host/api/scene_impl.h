// What a public ray::api::Scene holds: its scene document, and the internal flattened
// Scene both renderers take, kept flattened from it after every edit.
#pragma once

#include <functional>
#include <vector>

#include "ray/scene.h"
#include "scene/scene.h"
#include "scene/scene_document.h"
#include "scene/scene_loader.h"

namespace ray::api {

struct Scene::Impl {
    static ray::LoadOptions quietOptions() {
        ray::LoadOptions options;
        options.warn = [](const std::string&) {};
        return options;
    }

    ray::SceneDocument document;  // the scene as its file has it (scene/scene_document.h)
    ray::Resources resources;     // its images and meshes, and those added in code
    ray::Scene scene;             // the document flattened: what Renderers take
    std::vector<ray::Material> materials;  // addMaterial's handles
    // How it was loaded; warnings after loading are not reported (loading reported them).
    ray::LoadOptions options = quietOptions();

    // Applies `change` to a copy of the document, flattens the copy, and keeps both;
    // when either throws (InputError, public), nothing has changed.
    void edit(const std::function<void(ray::SceneDocument&)>& change);
};

}  // namespace ray::api
