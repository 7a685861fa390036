// What a public ray::api::Scene holds: the editing service (edit/edit_session.h) over its
// scene document, the same service ray view's page edits through, without history (a
// program keeps its own), and the material handles of addMaterial.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <vector>

#include "edit/edit_session.h"
#include "edit/file_stamp.h"
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
    static ray::edit::SessionOptions sessionOptions(const ray::LoadOptions& load) { return {load, false, {}}; }

    explicit Impl(ray::SceneDocument document = {}, const ray::LoadOptions& load = quietOptions())
        : session(std::move(document), sessionOptions(load)) {}

    // The document, its images and meshes, and the document flattened: what Renderers take.
    // Every change makes a new flattened scene whose lineage (scene/scene_changes.h) says
    // what changed, so that a Renderer's frame source re-packs that alone.
    ray::edit::EditSession session;
    std::vector<ray::Material> materials;  // addMaterial's handles
    // The files this scene was loaded from or saved to, as it read or wrote them (by their
    // absolute path): a save does not replace one another program has changed since.
    std::map<std::filesystem::path, ray::edit::FileStamp> files;

    const ray::SceneDocument& document() const { return session.document(); }
    std::shared_ptr<const ray::Scene> flattened() const { return session.scene(); }
};

}  // namespace ray::api
