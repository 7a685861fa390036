#include "opencl/packed_scene_cache.h"

#include <chrono>
#include <optional>
#include <string_view>
#include <utility>

#include "core/steady_clock.h"
#include "scene/scene_difference.h"

namespace ray::engine {

namespace {

// Whether repackScene writes table `name` anew for `changes` (scene_packing.cpp: a refit
// rewrites the trees, the primitives and their motions; a primitive's material its record;
// a material or a texture the materials; a light the lights; a texture the textures). The
// others keep their version, so that no device uploads them again.
bool repacked(std::string_view name, const SceneChanges& changes) {
    if (changes.geometry && (name == "nodes" || name == "cpuNodes" || name == "motions" || name == "primitives"))
        return true;
    if (changes.primitiveMaterials && name == "primitives") return true;
    if ((changes.materials || changes.images) && name == "materials") return true;
    if (changes.lights && name == "lights") return true;
    return changes.images && (name == "textures" || name == "texels");
}

}  // namespace

void PackedSceneCache::update(const RenderSettings& settings, RenderStats& stats,
                              const std::function<void()>& releaseOldTables) {
    const int side = areaLightGridSide(settings);
    const bool tri = settings.textureFilter == TextureFilter::Trilinear;
    const bool sameShape = packed_ && side == packedGridSide_ && tri == packedTrilinear_;
    stats.sceneUpdate = {};
    if (sameShape && packedScene_ == scene_) return;
    if (sameShape && repackEdit(settings, stats)) return;
    // Idle devices let go of the old tables now (CPU devices read them in place); a busy one
    // keeps them alive until it uploads the new ones.
    packed_.reset();
    releaseOldTables();
    const auto start = std::chrono::steady_clock::now();
    auto fresh = std::make_shared<PackedScene>(packScene(*scene_, settings, cpuTables_));
    for (uint64_t& version : fresh->versions) version = ++tableVersions_;
    stats.packSeconds = secondsSince(start);
    stats.bvhBuildSeconds = fresh->bvhBuildSeconds;
    stats.meshPackedBytes = fresh->meshBytes();
    stats.sceneUpdate.packing = "full";
    stats.sceneUpdate.bvh = "rebuilt";
    fresh->forEachBuffer([&](const auto&, SceneBufferName name) { stats.sceneUpdate.tables.push_back(name.name); });
    packed_ = std::move(fresh);
    packedScene_ = scene_;
    packedGridSide_ = side;
    packedTrilinear_ = tri;
}

// After setScene, with tables of the same shape: nothing when the scene is the one packed
// (or changed in nothing a frame reads), else the edits repacked. What changed is what the
// edits said (the scene's lineage, scene/scene_changes.h); only a scene that does not
// descend from the packed one by edits (a file reloaded from disk), or another object of
// the same revision (a copy changed by hand, or a change of its camera alone), is compared
// with it. False when the change needs a whole packing.
bool PackedSceneCache::repackEdit(const RenderSettings& settings, RenderStats& stats) {
    const auto start = std::chrono::steady_clock::now();
    const uint64_t packedRevision = packedScene_->lineage.revision;
    const std::optional<SceneChanges> told = scene_->lineage.revision == packedRevision
                                                 ? std::nullopt
                                                 : scene_->lineage.changesSince(packedRevision);
    SceneChanges changes = told ? *told : compareScenes(*packedScene_, *scene_);
    changes.camera = false;  // each frame's camera is its own (renderFrame's)
    if (!changes.any()) {
        packedScene_ = scene_;
        return true;
    }
    std::optional<PackedScene> edited = repackScene(*packed_, *scene_, settings, changes);
    if (!edited) return false;
    size_t next = 0;
    edited->forEachBuffer([&](const auto&, SceneBufferName name) {
        const size_t i = next++;
        const bool fresh = repacked(name.name, changes);
        edited->versions[i] = fresh ? ++tableVersions_ : packed_->versions[i];
        if (fresh) stats.sceneUpdate.tables.push_back(name.name);
    });
    stats.packSeconds = secondsSince(start);
    stats.bvhBuildSeconds = 0;
    stats.sceneUpdate.packing = told ? "edit" : "compared";
    stats.sceneUpdate.bvh = changes.geometry ? "refit" : "kept";
    packed_ = std::make_shared<PackedScene>(std::move(*edited));
    packedScene_ = scene_;
    return true;
}

}  // namespace ray::engine
