// Packing a flattened Scene into the device buffers of cl/shared_types.h.
#pragma once

#include <cstdint>
#include <vector>

#include "bvh.h"
#include "render_settings.h"
#include "scene.h"
#include "shared_types.h"

namespace ray {

struct PackedScene {
    std::vector<gpu::RayBvhNode> nodes;
    std::vector<gpu::RayPrimitive> primitives;  // in BVH order
    std::vector<gpu::RayMaterial> materials;
    std::vector<gpu::RayLight> lights;
    std::vector<gpu::RayTexture> textures;      // one per Scene::images entry
    std::vector<uint8_t> texels;                // RGBA8, all textures back to back
    double bvhBuildSeconds = 0;

    size_t totalBytes() const;
};

// Builds the BVH and packs everything. Throws InputError for primitives the kernel cannot
// draw yet.
PackedScene packScene(const Scene& scene);

// The launch parameters for an image (the tile fields are set per launch).
gpu::RayRenderParams makeRenderParams(const Scene& scene, const RenderSettings& settings, const PackedScene& packed);

// How far secondary and shadow rays start off a surface, relative to the magnitude of
// the hit point's coordinates (see offsetFromSurface in cl/shading.cl).
constexpr float kKernelRayOffset = 1e-4f;

}  // namespace ray
