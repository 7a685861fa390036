// What a public ray::api::Scene holds: its scene document, and the internal flattened
// Scene both renderers take, kept flattened from it after every edit.
#pragma once

#include <cstdint>
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
    // Which state `scene` is in: a number no other state of any Scene had (copies share
    // it with their source), set anew by every change but the camera's (changed()), which
    // each frame reads for itself. A Renderer takes the flattened scene again only when
    // its revision differs from the one it rendered last.
    uint64_t revision = newRevision();
    std::vector<ray::Material> materials;  // addMaterial's handles
    // How it was loaded; warnings after loading are not reported (loading reported them).
    ray::LoadOptions options = quietOptions();

    static uint64_t newRevision();
    void changed() { revision = newRevision(); }

    // Applies `change` to a copy of the document, flattens the copy, and keeps both;
    // when either throws (InputError, public), nothing has changed.
    void edit(const std::function<void(ray::SceneDocument&)>& change);
};

}  // namespace ray::api
