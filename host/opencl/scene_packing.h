// Packing a flattened Scene into the device buffers of cl/shared_types.h.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "accel/bvh.h"
#include "render/render_settings.h"
#include "scene/scene.h"
#include "scene/scene_difference.h"
#include "shared_types.h"

namespace ray {

// What a scene's buffer is called: its name in the kernel, and what it holds in words
// (cl/shared_types.h RAY_SCENE_BUFFERS).
struct SceneBufferName {
    const char* name;  // "nodes"
    const char* what;  // "BVH nodes"
    bool cpuOnly;      // read by CPU devices' kernels alone (RAY_CPU_DEVICES)
};

// How many buffers the scene has: renderTile's scene parameters.
#define RAY_COUNT_SCENE_BUFFER(Type, name, what, readers) +1
constexpr size_t kSceneBufferCount = 0 RAY_SCENE_BUFFERS(RAY_COUNT_SCENE_BUFFER);
#undef RAY_COUNT_SCENE_BUFFER

// The scene as the kernel reads it: a table for each of its buffers (cl/shared_types.h
// RAY_SCENE_BUFFERS, which says what each holds), and what the packing keeps besides.
struct PackedScene {
#define RAY_SCENE_TABLE(Type, name, what, readers) std::vector<gpu::Type> name;
    RAY_SCENE_BUFFERS(RAY_SCENE_TABLE)
#undef RAY_SCENE_TABLE
    // meshRoots[i]: mesh i's root node in `nodes` (its BVH's nodes follow the scene's).
    std::vector<int> meshRoots;
    // primitiveOrder[i]: the scene's primitive at place i of the primitives table (BVH
    // order); sceneNodes: how many of `nodes` are the scene's tree (the meshes' follow).
    // Kept so that an edit can repack the records or refit the tree (repackScene).
    std::vector<uint32_t> primitiveOrder;
    size_t sceneNodes = 0;
    // Whether the tables only CPU devices read (cpuNodes) are packed: some device of the
    // engine's runs a CPU kernel (opencl/kernel_variant.h). Kept so that repackScene does too.
    bool cpuTables = true;
    double bvhBuildSeconds = 0;
    // Each table's version: equal in two packings when the table is the same, so that a
    // device holding one packing uploads only the tables another changed (scene_upload.h uploadScene).
    std::array<uint64_t, kSceneBufferCount> versions{};

    // Calls visit(table, SceneBufferName) for each table, in the list's order: the order of
    // renderTile's scene parameters.
    template <class Visit>
    void forEachBuffer(Visit&& visit) const {
#define RAY_VISIT_SCENE_TABLE(Type, name, what, readers) \
    visit(name, SceneBufferName{#name, what, readers == RAY_CPU_DEVICES});
        RAY_SCENE_BUFFERS(RAY_VISIT_SCENE_TABLE)
#undef RAY_VISIT_SCENE_TABLE
    }

    size_t totalBytes() const;  // of all the tables
    size_t meshBytes() const;   // of the meshes' nodes, triangle and shading records
};

// Builds the BVHs (the scene's over instances, one per mesh over its triangles) and packs
// everything, the tables that only CPU devices read (cl/shared_types.h RAY_CPU_DEVICES) when
// cpuTables says some device will (KernelVariant::reads); they are left empty otherwise.
// Settings that shape the buffers: the area lights' sample grid.
PackedScene packScene(const Scene& scene, const RenderSettings& settings = {}, bool cpuTables = true);

// An edited scene packed from the packing of the scene before the edit (`previous`, made
// with the same settings), when their difference (compareScenes(before, scene)) has no
// geometry or only moved primitives: the tables of what changed are packed again (the
// materials, the lights, the textures, the primitive records), the others copied; moved
// primitives have the scene's tree refitted around their new boxes (the tree keeps its
// shape and order, so no BVH is built: bvhBuildSeconds is 0, the meshes' trees are kept).
// Returns nothing when the difference needs a whole packing (packScene).
std::optional<PackedScene> repackScene(const PackedScene& previous, const Scene& scene, const RenderSettings& settings,
                                       const SceneDifference& difference);

// The launch parameters for an image (the tile fields are set per launch).
gpu::RayRenderParams makeRenderParams(const Scene& scene, const RenderSettings& settings, const PackedScene& packed);
// The same from another camera than the scene's (the engine's frames).
gpu::RayRenderParams makeRenderParams(const Camera& camera, const GlobalCoefficients& globals,
                                      const RenderSettings& settings, const PackedScene& packed);

// How far secondary and shadow rays start off a surface, relative to the magnitude of
// the hit point's coordinates (see surfaceClearance in cl/shading/shading.cl).
constexpr float kKernelRayOffset = 1e-4f;

}  // namespace ray
