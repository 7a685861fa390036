#include "scene_packing.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>

namespace ray {

// The layouts must agree with OpenCL C's (cl/shared_types.h): float4/int4 fields only,
// each 16 bytes, no padding anywhere.
static_assert(sizeof(gpu::float4) == 16 && alignof(gpu::float4) == 16);
static_assert(sizeof(gpu::int4) == 16 && alignof(gpu::int4) == 16);
static_assert(sizeof(gpu::RayBvhNode) == 64);
static_assert(offsetof(gpu::RayBvhNode, links) == 48);
static_assert(sizeof(gpu::RayPrimitive) == 64);
static_assert(offsetof(gpu::RayPrimitive, info) == 48);
static_assert(sizeof(gpu::RayMaterial) == 128);
static_assert(offsetof(gpu::RayMaterial, maps) == 112);
static_assert(sizeof(gpu::RayLight) == 112);
static_assert(offsetof(gpu::RayLight, area) == 96);
static_assert(sizeof(gpu::RayTexture) == 16);
static_assert(sizeof(gpu::RayRenderParams) == 176);
static_assert(offsetof(gpu::RayRenderParams, tile) == 160);
static_assert(int(PrimitiveType::Cone) == RAY_PRIM_CONE && int(PrimitiveType::Mesh) == RAY_PRIM_MESH);
static_assert(int(LightType::Area) == RAY_LIGHT_AREA && int(LightType::Spot) == RAY_LIGHT_SPOT);
static_assert(int(AntialiasMode::Course) == RAY_AA_COURSE && int(AntialiasMode::Adaptive) == RAY_AA_ADAPTIVE);

namespace {

gpu::float4 toFloat4(const Vec3& v, double w = 0) { return {float(v.x), float(v.y), float(v.z), float(w)}; }

void checkSupported(const Scene& scene) {
    for (const PrimitiveInstance& p : scene.primitives) {
        if (p.type == PrimitiveType::Torus || p.type == PrimitiveType::Mesh)
            throw InputError(scene.sourceFile.string() + ": error: " + primitiveTypeName(p.type) +
                             " primitives are not supported yet; remove them from the scene");
    }
}

gpu::RayPrimitive packPrimitive(const PrimitiveInstance& instance) {
    gpu::RayPrimitive p;
    for (int row = 0; row < 3; ++row) {
        const double* m = instance.worldToObject.m[row];
        p.worldToObject[row] = {float(m[0]), float(m[1]), float(m[2]), float(m[3])};
    }
    p.info = {int(instance.type), instance.material, instance.mesh, 0};
    return p;
}

gpu::RayMaterial packMaterial(const Material& m, const Scene& scene) {
    auto mapIndex = [&](const TextureMap& map) {
        return map.image >= 0 && !scene.images[size_t(map.image)].empty() ? map.image : -1;
    };
    gpu::RayMaterial g;
    g.diffuse = toFloat4(m.diffuse, m.blend);
    g.ambient = toFloat4(m.ambient, m.shininess);
    g.specular = toFloat4(m.specular, m.ior);
    g.reflective = toFloat4(m.reflective);
    g.transparent = toFloat4(m.transparent);
    g.emissive = toFloat4(m.emissive);
    g.repeats = {float(m.texture.repeatU), float(m.texture.repeatV), float(m.bumpMap.repeatU),
                 float(m.bumpMap.repeatV)};
    g.maps = {mapIndex(m.texture), mapIndex(m.bumpMap), 0, 0};
    return g;
}

gpu::RayLight packLight(const Light& light) {
    gpu::RayLight g;
    g.info = {int(light.type), 0, 0, 0};
    g.color = toFloat4(light.color);
    g.position = toFloat4(light.position);
    g.direction = toFloat4(normalize(light.direction));
    g.attenuation = toFloat4(light.attenuation);
    double outer = radians(light.angleDegrees);
    double inner = std::max(0.0, radians(light.angleDegrees - light.penumbraDegrees));
    g.spot = {float(std::cos(outer)), float(std::cos(inner)), float(outer), float(inner)};
    g.area = {float(light.width), float(light.height), 0, 0};
    return g;
}

void packTextures(const Scene& scene, PackedScene& packed) {
    for (const Image& image : scene.images) {
        int offset = int(packed.texels.size() / 4);
        packed.textures.push_back({{offset, image.width, image.height, 0}});
        for (size_t p = 0, n = size_t(image.width) * size_t(image.height); p < n; ++p) {
            for (int c = 0; c < 3; ++c)
                packed.texels.push_back(uint8_t(std::lround(std::clamp(image.rgb[p * 3 + size_t(c)], 0.0f, 1.0f) * 255.0f)));
            packed.texels.push_back(255);
        }
    }
}

}  // namespace

size_t PackedScene::totalBytes() const {
    return nodes.size() * sizeof(nodes[0]) + primitives.size() * sizeof(primitives[0]) +
           materials.size() * sizeof(materials[0]) + lights.size() * sizeof(lights[0]) +
           textures.size() * sizeof(textures[0]) + texels.size();
}

PackedScene packScene(const Scene& scene) {
    checkSupported(scene);
    PackedScene packed;

    auto start = std::chrono::steady_clock::now();
    std::vector<BoundingBox> bounds(scene.primitives.size());
    for (size_t i = 0; i < bounds.size(); ++i) bounds[i] = worldBounds(scene.primitives[i]);
    FlatBvh bvh = buildBvh(bounds);
    packed.bvhBuildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    packed.nodes = std::move(bvh.nodes);
    packed.primitives.reserve(scene.primitives.size());
    for (uint32_t index : bvh.primitiveOrder) packed.primitives.push_back(packPrimitive(scene.primitives[index]));
    for (const Material& m : scene.materials) packed.materials.push_back(packMaterial(m, scene));
    for (const Light& l : scene.lights) packed.lights.push_back(packLight(l));
    packTextures(scene, packed);
    return packed;
}

gpu::RayRenderParams makeRenderParams(const Scene& scene, const RenderSettings& s, const PackedScene& packed) {
    const Camera& camera = scene.camera;
    Vec3 forward = normalize(camera.look);
    Vec3 right = normalize(cross(forward, camera.up));
    Vec3 up = cross(right, forward);
    double h = std::tan(radians(camera.heightAngleDegrees) / 2);
    double w = h * double(s.width) / double(s.height);

    int features = 0;
    if (s.shadows) features |= RAY_FEATURE_SHADOWS;
    if (s.reflections) features |= RAY_FEATURE_REFLECTIONS;
    if (s.refraction) features |= RAY_FEATURE_REFRACTION;
    if (s.textures) features |= RAY_FEATURE_TEXTURES;
    if (s.depthOfField) features |= RAY_FEATURE_DOF;
    if (s.textureFilter != TextureFilter::Nearest) features |= RAY_FEATURE_BILINEAR;

    gpu::RayRenderParams p;
    p.eye = toFloat4(camera.position);
    p.right = toFloat4(right * w);
    p.up = toFloat4(up * h);
    p.forward = toFloat4(forward);
    // Depth of field: the lens radius (0: a pinhole), and the distance that stays sharp;
    // an unset focal length focuses where the camera looks (|look|, the focus point for a
    // camera given by <focus>), as the reference renderer does.
    double lensRadius = s.depthOfField ? camera.aperture / 2 : 0;
    double focalDistance = camera.focalLength > 0 ? camera.focalLength : length(camera.look);
    p.lens = {float(lensRadius), float(focalDistance), 0, 0};
    const GlobalCoefficients& g = scene.globals;
    p.globals = {float(g.ka), float(g.kd), float(g.ks), float(g.kt)};
    p.limits = {float(s.weightThreshold), kKernelRayOffset, 0, 0};
    p.image = {s.width, s.height, 0, 0};
    p.mode = {int(s.antialias), s.maxDepth, features, s.samples};
    p.counts = {int(packed.lights.size()), int(packed.primitives.size()), int(packed.nodes.size()), int(s.seed)};
    return p;
}

}  // namespace ray
