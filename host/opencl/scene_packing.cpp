#include "opencl/scene_packing.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <array>
#include <cstddef>
#include <future>
#include <thread>

#include "accel/wide_bvh.h"
#include "image/mipmap.h"
#include "render/texture_footprint.h"

namespace ray {

// The values the kernel's constants stand for (the layouts are checked in cl/shared_types.h).
static_assert(int(PrimitiveType::Cone) == RAY_PRIM_CONE && int(PrimitiveType::Mesh) == RAY_PRIM_MESH);
static_assert(int(PrimitiveType::Csg) == RAY_PRIM_CSG);
static_assert(kCsgMaxOperands == RAY_CSG_MAX_OPERANDS && kCsgMaxStack == RAY_CSG_MAX_STACK);
static_assert(int(LightType::Area) == RAY_LIGHT_AREA && int(LightType::Spot) == RAY_LIGHT_SPOT);
static_assert(int(AntialiasMode::Course) == RAY_AA_COURSE && int(AntialiasMode::Adaptive) == RAY_AA_ADAPTIVE);

namespace {

gpu::float4 toFloat4(const Vec3& v) { return {float(v.x), float(v.y), float(v.z), 0}; }

// order: the tie-breaking rank of cl/shared_types.h (the instance's index in the scene).
gpu::RayPrimitive packPrimitive(const PrimitiveInstance& instance, int order, const std::vector<int>& meshRoots) {
    gpu::RayPrimitive p{};
    for (int row = 0; row < 3; ++row) {
        const double* m = instance.worldToObject.m[row];
        p.worldToObject[row] = {float(m[0]), float(m[1]), float(m[2]), float(m[3])};
    }
    p.type = int(instance.type);
    p.material = instance.material;
    p.order = order;
    p.geometry = instance.type == PrimitiveType::Mesh ? meshRoots[size_t(instance.mesh)] : -1;
    return p;
}

// A csg program's record that is not an operand: an operator, or the program's end.
gpu::RayPrimitive csgStepRecord(int type) {
    gpu::RayPrimitive record{};
    record.type = type;
    record.material = 0;
    record.order = -1;
    record.geometry = -1;
    return record;
}

// Every csg object's program, appended to the primitive buffer and ended by a RAY_CSG_END
// record (cl/shared_types.h), and the program's place in the csg object's own record (in BVH
// order already in packed).
void packCsgPrograms(const Scene& scene, const std::vector<uint32_t>& bvhOrder, PackedScene& packed) {
    // Each object's operands break ties with the rank of its first instance.
    std::vector<int> firstInstance(scene.csgObjects.size(), -1);
    for (size_t i = 0; i < scene.primitives.size(); ++i)
        if (const PrimitiveInstance& instance = scene.primitives[i];
            instance.type == PrimitiveType::Csg && firstInstance[size_t(instance.csg)] < 0)
            firstInstance[size_t(instance.csg)] = int(i);
    std::vector<int> programStart;
    for (size_t k = 0; k < scene.csgObjects.size(); ++k) {
        programStart.push_back(int(packed.primitives.size()));
        for (const CsgStep& step : scene.csgObjects[k].program) {
            if (step.kind == CsgStepKind::Operand) {
                packed.primitives.push_back(
                    packPrimitive(scene.csgOperands[size_t(step.operand)], firstInstance[k], packed.meshRoots));
                continue;
            }
            packed.primitives.push_back(csgStepRecord(step.kind == CsgStepKind::Union          ? RAY_CSG_UNION
                                                      : step.kind == CsgStepKind::Intersection ? RAY_CSG_INTERSECTION
                                                                                               : RAY_CSG_DIFFERENCE));
        }
        packed.primitives.push_back(csgStepRecord(RAY_CSG_END));
    }
    for (size_t i = 0; i < bvhOrder.size(); ++i) {
        const PrimitiveInstance& instance = scene.primitives[bvhOrder[i]];
        if (instance.type == PrimitiveType::Csg) packed.primitives[i].geometry = programStart[size_t(instance.csg)];
    }
}

gpu::RayMaterial packMaterial(const Material& m, const Scene& scene) {
    auto mapIndex = [&](const TextureMap& map) {
        return map.image >= 0 && !scene.images[size_t(map.image)].empty() ? map.image : -1;
    };
    gpu::RayMaterial g{};
    g.diffuse = toFloat4(m.diffuse);
    g.ambient = toFloat4(m.ambient);
    g.specular = toFloat4(m.specular);
    g.reflective = toFloat4(m.reflective);
    g.transparent = toFloat4(m.transparent);
    g.emissive = toFloat4(m.emissive);
    g.blend = float(m.blend);
    g.shininess = float(m.shininess);
    g.ior = float(m.ior);
    g.textureRepeat = {float(m.texture.repeatU), float(m.texture.repeatV)};
    g.bumpRepeat = {float(m.bumpMap.repeatU), float(m.bumpMap.repeatV)};
    g.textureMap = mapIndex(m.texture);
    g.bumpMap = mapIndex(m.bumpMap);
    return g;
}

gpu::RayLight packLight(const Light& light, const RenderSettings& settings) {
    gpu::RayLight g{};
    g.type = int(light.type);
    g.areaSamples = areaLightGridSide(settings);
    g.color = toFloat4(light.color);
    g.position = toFloat4(light.position);
    g.direction = toFloat4(normalize(light.direction));
    g.constantAttenuation = float(light.attenuation.x);
    g.linearAttenuation = float(light.attenuation.y);
    g.quadraticAttenuation = float(light.attenuation.z);
    // inner = angle − penumbra as SPEC §4 writes it, negative when the penumbra is wider
    // than the cone (spotlight_on_cheese.xml: penumbra 80 with the default angle 45): the
    // smooth step then starts outside the cone's axis, so even the axis is dimmed.
    g.outerAngle = float(radians(light.angleDegrees));
    g.innerAngle = float(radians(light.angleDegrees - light.penumbraDegrees));
    g.width = float(light.width);
    g.height = float(light.height);
    return g;
}

// A direction of the triangle table, three floats (RayTriangleShading).
void storeFloat3(float (&out)[3], const Vec3& v) {
    out[0] = float(v.x);
    out[1] = float(v.y);
    out[2] = float(v.z);
}

gpu::float2 texCoord(const TriangleMesh& mesh, const MeshCorner& corner) {
    if (corner.texCoord < 0) return {};
    const std::array<double, 2>& uv = mesh.texCoords[size_t(corner.texCoord)];
    return {float(uv[0]), float(uv[1])};
}

// Below this many primitives the per-primitive loops run on one thread: starting threads
// would cost more than they save.
constexpr size_t kParallelPackThreshold = 65536;

// Runs body(begin, end) over slices of [0, n), one per core when n is large: the bounds and
// the primitive records of a scene of millions of instances (recursiveSpheres10: 2.9
// million) are independent of one another, and each is a gather from the 200-byte
// instances that waits on memory. The slices write disjoint elements.
template <class Body>
void forEachSlice(size_t n, const Body& body) {
    const size_t threads = n < kParallelPackThreshold ? 1 : std::max(1u, std::thread::hardware_concurrency());
    const size_t slice = (n + threads - 1) / threads;
    std::vector<std::future<void>> others;
    for (size_t t = 1; t < threads; ++t)
        others.push_back(std::async(std::launch::async, body, std::min(n, t * slice), std::min(n, (t + 1) * slice)));
    body(size_t(0), std::min(n, slice));
    for (std::future<void>& f : others) f.get();
}

// Triangle i's shading record: its corners' normals (the face's where the file gave none),
// texture coordinates and tangent frame.
gpu::RayTriangleShading shadingRecord(const TriangleMesh& mesh, uint32_t i, float uvDensity) {
    const std::array<MeshCorner, 3>& t = mesh.triangles[i];
    gpu::RayTriangleShading s{};
    bool smooth = t[0].normal >= 0 && t[1].normal >= 0 && t[2].normal >= 0;
    Vec3 face = mesh.faceNormal(i);
    storeFloat3(s.normal0, smooth ? normalize(mesh.normals[size_t(t[0].normal)]) : face);
    storeFloat3(s.normal1, smooth ? normalize(mesh.normals[size_t(t[1].normal)]) : face);
    storeFloat3(s.normal2, smooth ? normalize(mesh.normals[size_t(t[2].normal)]) : face);
    storeFloat3(s.uTangent, mesh.uTangent(i));
    if (t[0].texCoord >= 0 && t[1].texCoord >= 0 && t[2].texCoord >= 0) {
        s.uv0 = texCoord(mesh, t[0]);
        s.uv1 = texCoord(mesh, t[1]);
        s.uv2 = texCoord(mesh, t[2]);
    }
    s.uvDensity = uvDensity;
    s.uvHandedness = float(mesh.uvHandedness(i));
    return s;
}

// The first BVH-order position of each leaf of a mesh's tree, ascending: the leaves cover
// the positions in order, so leaf j holds [starts[j], starts[j + 1]) and is record j.
std::vector<int> leafStarts(const std::vector<gpu::RayWideBvhNode>& wide) {
    std::vector<int> starts;
    for (const gpu::RayWideBvhNode& node : wide)
        for (int c = 0; c < 4; ++c)
            if ((&node.count.x)[c] > 0) starts.push_back((&node.index.x)[c]);
    std::sort(starts.begin(), starts.end());
    return starts;
}

// Triangle `i` of the mesh into lane `lane` of a record (RayTriangle4).
void storeTriangle(const TriangleMesh& mesh, uint32_t i, int lane, gpu::RayTriangle4& record) {
    const Vec3 p0 = mesh.corner(i, 0), e1 = mesh.corner(i, 1) - p0, e2 = mesh.corner(i, 2) - p0;
    gpu::float4* rows[9] = {&record.p0x, &record.p0y, &record.p0z, &record.e1x, &record.e1y,
                            &record.e1z, &record.e2x, &record.e2y, &record.e2z};
    const Vec3* vectors[3] = {&p0, &e1, &e2};
    for (int v = 0; v < 3; ++v)
        for (int axis = 0; axis < 3; ++axis) (&rows[3 * v + axis]->x)[lane] = float((*vectors[v])[axis]);
}

// One mesh: its BVH's nodes appended to packed.nodes (child indices rebased to their place
// there), its triangles in BVH order, a leaf's (at most four) in one record, each leaf's link
// rebased to its record's first slot. Returns the root node's index. The tree is built for
// records (BvhBuildOptions::leafBlock), so that its leaves are nearly full. The per-leaf loop
// runs on every core (each leaf's records are its own), so a mesh of millions packs at
// memory speed.
int packMesh(const TriangleMesh& mesh, PackedScene& packed) {
    const float uvDensity = float(meshUvDensity(mesh));  // every triangle's (trilinear filtering)
    std::vector<BoundingBox> bounds(mesh.triangles.size());
    forEachSlice(bounds.size(), [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            for (int k = 0; k < 3; ++k) {
                const Vec3& p = mesh.corner(i, k);
                BoundingBox corner;
                for (int axis = 0; axis < 3; ++axis) corner.min[axis] = corner.max[axis] = float(p[axis]);
                bounds[i].expand(corner);
            }
        }
    });
    BvhBuildOptions recordLeaves;
    recordLeaves.maxLeafSize = RAY_TRIANGLES_PER_RECORD;
    recordLeaves.leafBlock = RAY_TRIANGLES_PER_RECORD;
    FlatBvh bvh = buildBvh(bounds, recordLeaves);
    std::vector<BoundingBox>().swap(bounds);
    const int nodeOffset = int(packed.nodes.size()), recordOffset = int(packed.triangles.size());
    std::vector<gpu::RayWideBvhNode> wide = widenBvh(bvh.nodes);
    std::vector<BinaryBvhNode>().swap(bvh.nodes);
    const std::vector<int> starts = leafStarts(wide);
    // Grown once for the mesh, not node by node (each regrowth copies the table), and at
    // least doubled, so that a scene of many meshes still copies it a few times only.
    const size_t needed = packed.nodes.size() + wide.size();
    if (packed.nodes.capacity() < needed) packed.nodes.reserve(std::max(needed, 2 * packed.nodes.capacity()));
    for (gpu::RayWideBvhNode node : wide) {
        int* index = &node.index.x;
        const int* count = &node.count.x;
        for (int c = 0; c < 4; ++c) {
            if (index[c] < 0) continue;
            if (count[c] == 0) {
                index[c] += nodeOffset;
            } else {
                const int record = int(std::lower_bound(starts.begin(), starts.end(), index[c]) - starts.begin());
                index[c] = (recordOffset + record) * RAY_TRIANGLES_PER_RECORD;
            }
        }
        packed.nodes.push_back(node);
    }
    // Copied into the node table: freed before the triangle tables grow, so that the mesh's
    // nodes are not held twice at the process's peak.
    std::vector<gpu::RayWideBvhNode>().swap(wide);
    const size_t records = starts.size(), triangles = bvh.primitiveOrder.size();
    packed.triangles.resize(size_t(recordOffset) + records);
    packed.triangleShading.resize((size_t(recordOffset) + records) * RAY_TRIANGLES_PER_RECORD);
    forEachSlice(records, [&](size_t begin, size_t end) {
        for (size_t leaf = begin; leaf < end; ++leaf) {
            const size_t first = size_t(starts[leaf]);
            const size_t last = leaf + 1 < records ? size_t(starts[leaf + 1]) : triangles;
            const size_t record = size_t(recordOffset) + leaf;
            for (size_t k = 0; first + k < last; ++k) {
                const uint32_t i = bvh.primitiveOrder[first + k];
                storeTriangle(mesh, i, int(k), packed.triangles[record]);
                packed.triangleShading[record * RAY_TRIANGLES_PER_RECORD + k] = shadingRecord(mesh, i, uvDensity);
            }
        }
    });
    return nodeOffset;
}

void appendTexels(const Image& image, PackedScene& packed) {
    for (size_t p = 0, n = size_t(image.width) * size_t(image.height); p < n; ++p) {
        auto channel = [&](int c) {
            return uint8_t(std::lround(std::clamp(image.rgb[p * 3 + size_t(c)], 0.0f, 1.0f) * 255.0f));
        };
        packed.texels.push_back({channel(0), channel(1), channel(2), 255});
    }
}

// Each image, followed by its mipmap levels when filtering is trilinear (image/mipmap.h).
void packTextures(const Scene& scene, bool mipmaps, PackedScene& packed) {
    for (const Image& image : scene.images) {
        int offset = int(packed.texels.size());
        appendTexels(image, packed);
        int levelCount = 1;
        if (mipmaps && !image.empty()) {
            for (const Image& level : buildMipLevels(image)) {
                appendTexels(level, packed);
                ++levelCount;
            }
        }
        packed.textures.push_back({offset, image.width, image.height, levelCount});
    }
}

// Each primitive's motion in BVH order, or nothing when nothing moves.
void packMotions(const Scene& scene, PackedScene& packed) {
    packed.motions.clear();
    bool anyMotion = std::any_of(scene.primitives.begin(), scene.primitives.end(),
                                 [](const PrimitiveInstance& p) { return p.motion != Vec3{}; });
    if (anyMotion)
        for (uint32_t index : packed.primitiveOrder) packed.motions.push_back(toFloat4(scene.primitives[index].motion));
}

void setLane(gpu::float4& lanes, int lane, float value) { (&lanes.x)[lane] = value; }

// The box of a wide node's child `c` (one of the scene's tree: its leaves index the
// primitives table), refitted bottom up from the primitives' boxes of `scene`.
BoundingBox refitNode(const Scene& scene, PackedScene& packed, const std::vector<BoundingBox>& bounds, int node) {
    BoundingBox all;
    for (int c = 0; c < 4; ++c) {
        gpu::RayWideBvhNode& n = packed.nodes[size_t(node)];
        const int index = (&n.index.x)[c], count = (&n.count.x)[c];
        if (index < 0) continue;
        BoundingBox box;
        if (count > 0) {
            for (int k = index; k < index + count; ++k) box.expand(bounds[packed.primitiveOrder[size_t(k)]]);
        } else {
            box = refitNode(scene, packed, bounds, index);
        }
        gpu::RayWideBvhNode& m = packed.nodes[size_t(node)];  // the same node: refitNode does not grow the table
        setLane(m.minX, c, box.min[0]);
        setLane(m.minY, c, box.min[1]);
        setLane(m.minZ, c, box.min[2]);
        setLane(m.maxX, c, box.max[0]);
        setLane(m.maxY, c, box.max[1]);
        setLane(m.maxZ, c, box.max[2]);
        all.expand(box);
    }
    return all;
}

// Moved primitives: the scene's tree keeps its shape (and the primitives their places in
// it), each node's boxes grown or shrunk to what its primitives cover now. Rays walk it
// as they walk a new tree; a tree refitted after large moves is slower, not wrong.
void refitSceneTree(const Scene& scene, PackedScene& packed) {
    if (packed.sceneNodes == 0 || scene.primitives.empty()) return;
    std::vector<BoundingBox> bounds(scene.primitives.size());
    forEachSlice(bounds.size(), [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) bounds[i] = worldBounds(scene.primitives[i]);
    });
    refitNode(scene, packed, bounds, 0);
    if (packed.cpuTables) packed.cpuNodes = widenBvhForCpu(packed.nodes);
}

}  // namespace

size_t PackedScene::totalBytes() const {
    size_t bytes = 0;
    forEachBuffer([&](const auto& table, SceneBufferName) { bytes += table.size() * sizeof(table[0]); });
    return bytes;
}

size_t PackedScene::meshBytes() const {
    return (nodes.size() - sceneNodes) * sizeof(nodes[0]) + triangles.size() * sizeof(triangles[0]) +
           triangleShading.size() * sizeof(triangleShading[0]);
}

PackedScene packScene(const Scene& scene, const RenderSettings& settings, bool cpuTables) {
    PackedScene packed;
    packed.cpuTables = cpuTables;

    auto start = std::chrono::steady_clock::now();
    std::vector<BoundingBox> bounds(scene.primitives.size());
    forEachSlice(bounds.size(), [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) bounds[i] = worldBounds(scene.primitives[i]);
    });
    FlatBvh bvh = buildBvh(bounds);
    std::vector<BoundingBox>().swap(bounds);
    packed.nodes = widenBvh(bvh.nodes);
    // The binary tree is done with (its primitive order is not): freed before the tables
    // grow, it is no part of the process's peak.
    std::vector<BinaryBvhNode>().swap(bvh.nodes);
    packed.sceneNodes = packed.nodes.size();
    if (cpuTables) packed.cpuNodes = widenBvhForCpu(packed.nodes);
    for (const TriangleMesh& mesh : scene.meshes) packed.meshRoots.push_back(packMesh(mesh, packed));
    // The build time counts the meshes' trees with the scene's.
    packed.bvhBuildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    packed.primitives.resize(scene.primitives.size());
    forEachSlice(packed.primitives.size(), [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            const uint32_t index = bvh.primitiveOrder[i];
            packed.primitives[i] = packPrimitive(scene.primitives[index], int(index), packed.meshRoots);
        }
    });
    packCsgPrograms(scene, bvh.primitiveOrder, packed);
    packed.primitiveOrder = std::move(bvh.primitiveOrder);
    packMotions(scene, packed);
    for (const Material& m : scene.materials) packed.materials.push_back(packMaterial(m, scene));
    for (const Light& l : scene.lights) packed.lights.push_back(packLight(l, settings));
    packTextures(scene, settings.textureFilter == TextureFilter::Trilinear, packed);
    return packed;
}

std::optional<PackedScene> repackScene(const PackedScene& previous, const Scene& scene, const RenderSettings& settings,
                                       const SceneDifference& difference) {
    if (difference.geometry && !difference.transformsOnly) return std::nullopt;
    if (previous.primitiveOrder.size() != scene.primitives.size()) return std::nullopt;
    PackedScene packed = previous;
    packed.bvhBuildSeconds = 0;
    if (difference.geometry) {
        refitSceneTree(scene, packed);
        packMotions(scene, packed);
    }
    if (difference.geometry || difference.primitiveMaterials) {
        packed.primitives.clear();
        packed.primitives.resize(scene.primitives.size());
        forEachSlice(packed.primitives.size(), [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) {
                const uint32_t index = packed.primitiveOrder[i];
                packed.primitives[i] = packPrimitive(scene.primitives[index], int(index), packed.meshRoots);
            }
        });
        packCsgPrograms(scene, packed.primitiveOrder, packed);
    }
    if (difference.materials || difference.images) {
        packed.materials.clear();
        for (const Material& m : scene.materials) packed.materials.push_back(packMaterial(m, scene));
    }
    if (difference.lights) {
        packed.lights.clear();
        for (const Light& l : scene.lights) packed.lights.push_back(packLight(l, settings));
    }
    if (difference.images) {
        packed.textures.clear();
        packed.texels.clear();
        packTextures(scene, settings.textureFilter == TextureFilter::Trilinear, packed);
    }
    return packed;
}

gpu::RayRenderParams makeRenderParams(const Scene& scene, const RenderSettings& s, const PackedScene& packed) {
    return makeRenderParams(scene.camera, scene.globals, s, packed);
}

gpu::RayRenderParams makeRenderParams(const Camera& camera, const GlobalCoefficients& g, const RenderSettings& s,
                                      const PackedScene& packed) {
    Vec3 forward = normalize(camera.look);
    Vec3 right = normalize(cross(forward, camera.up));
    Vec3 up = cross(right, forward);
    double h = std::tan(radians(camera.heightAngleDegrees) / 2);
    double w = h * double(s.width) / double(s.height);

    int features = 0;
    if (s.shadows) features |= RAY_FEATURE_SHADOWS;
    if (s.reflections) features |= RAY_FEATURE_REFLECTIONS;
    if (s.refraction) features |= RAY_FEATURE_REFRACTION;
    if (s.fresnel) features |= RAY_FEATURE_FRESNEL;
    if (s.courseMeshes) features |= RAY_FEATURE_COURSE_MESHES;
    if (s.dofMode == DofMode::Disk) features |= RAY_FEATURE_LENS_DISK;
    if (s.textures) features |= RAY_FEATURE_TEXTURES;
    if (s.textureFilter == TextureFilter::Bilinear || s.textureFilter == TextureFilter::Trilinear)
        features |= RAY_FEATURE_BILINEAR;
    if (s.textureFilter == TextureFilter::Course) features |= RAY_FEATURE_COURSE_FILTER;
    if (s.textureFilter == TextureFilter::Trilinear) features |= RAY_FEATURE_TRILINEAR;

    gpu::RayRenderParams p{};
    p.eye = toFloat4(camera.position);
    p.right = toFloat4(right * w);
    p.up = toFloat4(up * h);
    p.forward = toFloat4(forward);
    // Depth of field: the lens radius (0: a pinhole), and the distance that stays sharp;
    // an unset focal length focuses where the camera looks (|look|, the focus point for a
    // camera given by <focus>), as the reference renderer does.
    double lensRadius = s.depthOfField ? camera.aperture / 2 : 0;
    double focalDistance = camera.focalLength > 0 ? camera.focalLength : length(camera.look);
    p.lensRadius = float(lensRadius);
    p.focalDistance = float(focalDistance);
    // Motion blur: the shutter, 0 (every ray at time 0, no motion read) when nothing moves.
    p.shutter = float(packed.motions.empty() ? 0 : s.shutter);
    p.pixelSpreadAngle = float(pixelSpreadAngle(camera.heightAngleDegrees, s.height));
    p.ka = float(g.ka);
    p.kd = float(g.kd);
    p.ks = float(g.ks);
    p.kt = float(g.kt);
    p.weightThreshold = float(s.weightThreshold);
    p.rayOffset = kKernelRayOffset;
    p.width = s.width;
    p.height = s.height;
    p.antialias = int(s.antialias);
    p.samples = s.samples;
    p.maxDepth = s.maxDepth;
    p.features = features;
    p.lightCount = int(packed.lights.size());
    p.seed = int(s.seed);
    return p;
}

}  // namespace ray
