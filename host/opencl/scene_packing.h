// Packing a flattened Scene into the device buffers of cl/shared_types.h.
#pragma once

#include <cstdint>
#include <vector>

#include "accel/bvh.h"
#include "render/render_settings.h"
#include "scene/scene.h"
#include "shared_types.h"

namespace ray {

struct PackedScene {
    std::vector<gpu::RayWideBvhNode> nodes;  // the four-wide BVH (host/accel/wide_bvh.h)
    std::vector<gpu::RayPrimitive> primitives;  // in BVH order
    std::vector<gpu::RayMaterial> materials;
    std::vector<gpu::RayLight> lights;
    std::vector<gpu::RayTexture> textures;      // one per Scene::images entry
    std::vector<uint8_t> texels;                // RGBA8, all textures back to back
    // Meshes: every mesh's triangles once, each mesh's in the order of its own BVH, whose
    // nodes follow the scene's in `nodes` (meshRoots[i]: mesh i's root node).
    std::vector<gpu::RayTriangle> triangles;
    std::vector<gpu::RayTriangleShading> triangleShading;
    std::vector<int> meshRoots;
    // Motion blur: each primitive's world-space motion (.xyz), parallel to `primitives`,
    // or empty when nothing in the scene moves. A buffer of its own rather than a fifth
    // float4 in RayPrimitive: static scenes keep their 64-byte (one cache line)
    // primitives, and the kernel reads a motion only for a ray whose time is not 0.
    std::vector<gpu::float4> motions;
    double bvhBuildSeconds = 0;

    size_t totalBytes() const;
};

// Builds the BVHs (the scene's over instances, one per mesh over its triangles) and packs
// everything.
// Settings that shape the buffers: the area lights' sample grid.
PackedScene packScene(const Scene& scene, const RenderSettings& settings = {});

// The launch parameters for an image (the tile fields are set per launch).
gpu::RayRenderParams makeRenderParams(const Scene& scene, const RenderSettings& settings, const PackedScene& packed);
// The same from another camera than the scene's (the engine's frames).
gpu::RayRenderParams makeRenderParams(const Camera& camera, const GlobalCoefficients& globals,
                                      const RenderSettings& settings, const PackedScene& packed);

// How far secondary and shadow rays start off a surface, relative to the magnitude of
// the hit point's coordinates (see surfaceClearance in cl/shading.cl).
constexpr float kKernelRayOffset = 1e-4f;

}  // namespace ray
