// The engine's packed scene (scene_packing.h), kept from frame to frame: packed on the first
// frame and again only when the scene changes (setScene, an editor's edit) or a setting that
// shapes the tables does (the area lights' sample grid, trilinear mipmaps). After an edit,
// only what the edit changed is packed again when it can be (repackScene: no BVH build for a
// material or light edit, a refit for moved primitives): the edits say what they changed
// (the scene's lineage, scene/scene_changes.h), and only a scene with no such word (a file
// reloaded from disk) is compared with the one packed. The tables re-packed get new
// versions and the others keep theirs, so that the devices upload those alone
// (scene_upload.h); the frame's RenderStats::sceneUpdate says which, and whether the BVH was
// kept, refitted or rebuilt.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>

#include "opencl/scene_packing.h"
#include "render/render_settings.h"
#include "render/render_stats.h"
#include "scene/scene.h"

namespace ray::engine {

class PackedSceneCache {
public:
    // cpuTables: whether some device walks the tables CPU devices alone read (packScene).
    PackedSceneCache(std::shared_ptr<const Scene> scene, bool cpuTables)
        : scene_(std::move(scene)), cpuTables_(cpuTables) {}

    // The scene of the next frames.
    void setScene(std::shared_ptr<const Scene> scene) { scene_ = std::move(scene); }
    const Scene& scene() const { return *scene_; }

    // Packs what the frame needs packed, if anything, and adds the seconds it took to
    // `stats` (packSeconds, bvhBuildSeconds). Before a whole new packing it lets go of the
    // old one and calls `releaseOldTables`, so that idle devices let go of their buffers of
    // it (CPU devices read the tables in place) before the new one takes its memory.
    void update(const RenderSettings& settings, RenderStats& stats, const std::function<void()>& releaseOldTables);

    // The current packing, shared with the devices that upload it.
    const std::shared_ptr<const PackedScene>& packed() const { return packed_; }

private:
    bool repackEdit(const RenderSettings& settings, RenderStats& stats);

    std::shared_ptr<const Scene> scene_;        // what the next frame renders
    std::shared_ptr<const Scene> packedScene_;  // what packed_ was packed from
    std::shared_ptr<const PackedScene> packed_;
    int packedGridSide_ = -1;
    bool packedTrilinear_ = false;
    uint64_t tableVersions_ = 0;  // the last version given to a packed table
    bool cpuTables_ = true;
};

}  // namespace ray::engine
