// The engine's packed scene (scene_packing.h), kept from frame to frame: packed on the first
// frame and again only when the scene changes (setScene, an editor's edit) or a setting that
// shapes the tables does (the area lights' sample grid, trilinear mipmaps). After an edit,
// only what differs is packed again when it can be (repackScene: no BVH build for a material
// or light edit, a refit for moved primitives), and each table that came out the same keeps
// its version, so that the devices keep its buffer (scene_upload.h).
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
