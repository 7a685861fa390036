#include "opencl/packed_scene_cache.h"

#include <array>
#include <chrono>
#include <cstring>
#include <optional>
#include <utility>

#include "core/steady_clock.h"

namespace ray::engine {

namespace {

// Each table's bytes, in the order of PackedScene::forEachBuffer.
std::array<std::pair<const void*, size_t>, kSceneBufferCount> tableBytes(const PackedScene& packed) {
    std::array<std::pair<const void*, size_t>, kSceneBufferCount> bytes;
    size_t next = 0;
    packed.forEachBuffer([&](const auto& table, SceneBufferName) {
        bytes[next++] = {table.data(), table.size() * sizeof(table[0])};
    });
    return bytes;
}

}  // namespace

void PackedSceneCache::update(const RenderSettings& settings, RenderStats& stats,
                              const std::function<void()>& releaseOldTables) {
    const int side = areaLightGridSide(settings);
    const bool tri = settings.textureFilter == TextureFilter::Trilinear;
    const bool sameShape = packed_ && side == packedGridSide_ && tri == packedTrilinear_;
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
    packed_ = std::move(fresh);
    packedScene_ = scene_;
    packedGridSide_ = side;
    packedTrilinear_ = tri;
}

// After setScene, with tables of the same shape: nothing when the scene is equal to the one
// packed, else the edit repacked. False when the edit needs a whole packing.
bool PackedSceneCache::repackEdit(const RenderSettings& settings, RenderStats& stats) {
    const auto start = std::chrono::steady_clock::now();
    SceneDifference difference = compareScenes(*packedScene_, *scene_);
    difference.camera = false;  // each frame's camera is its own (renderFrame's)
    if (!difference.any()) {
        packedScene_ = scene_;
        return true;
    }
    std::optional<PackedScene> edited = repackScene(*packed_, *scene_, settings, difference);
    if (!edited) return false;
    const auto before = tableBytes(*packed_), after = tableBytes(*edited);
    for (size_t i = 0; i < kSceneBufferCount; ++i) {
        const bool same = before[i].second == after[i].second &&
                          (before[i].second == 0 || std::memcmp(before[i].first, after[i].first, before[i].second) == 0);
        edited->versions[i] = same ? packed_->versions[i] : ++tableVersions_;
    }
    stats.packSeconds = secondsSince(start);
    stats.bvhBuildSeconds = 0;
    packed_ = std::make_shared<PackedScene>(std::move(*edited));
    packedScene_ = scene_;
    return true;
}

}  // namespace ray::engine
