#include "scene/scene_difference.h"

#include <cstring>

namespace ray {

namespace {

// Element by element, for vectors of types without padding (doubles, ints, floats).
template <class T>
bool sameBytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

bool sameAffine(const Affine& a, const Affine& b) {
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
            if (a.m[r][c] != b.m[r][c]) return false;
    return true;
}

// What an instance is, wherever it stands: its shape, mesh, csg object and object box.
bool sameKind(const PrimitiveInstance& a, const PrimitiveInstance& b) {
    return a.type == b.type && a.mesh == b.mesh && a.csg == b.csg && a.objectLo == b.objectLo &&
           a.objectHi == b.objectHi;
}

bool samePlace(const PrimitiveInstance& a, const PrimitiveInstance& b) {
    return a.motion == b.motion && sameAffine(a.objectToWorld, b.objectToWorld) &&
           sameAffine(a.worldToObject, b.worldToObject);
}

bool sameMesh(const TriangleMesh& a, const TriangleMesh& b) {
    static_assert(sizeof(MeshCorner) == 3 * sizeof(int));
    return sameBytes(a.positions, b.positions) && sameBytes(a.normals, b.normals) &&
           sameBytes(a.texCoords, b.texCoords) && sameBytes(a.triangles, b.triangles);
}

// The csg programs, and the operands but for where they stand (places: compare those too).
bool sameCsg(const Scene& a, const Scene& b, bool places) {
    if (a.csgObjects.size() != b.csgObjects.size() || a.csgOperands.size() != b.csgOperands.size()) return false;
    for (size_t i = 0; i < a.csgObjects.size(); ++i) {
        const auto& p = a.csgObjects[i].program;
        const auto& q = b.csgObjects[i].program;
        if (p.size() != q.size()) return false;
        for (size_t k = 0; k < p.size(); ++k)
            if (p[k].kind != q[k].kind || p[k].operand != q[k].operand) return false;
    }
    // An operand's material is packed with its shape (the csg program's records).
    for (size_t i = 0; i < a.csgOperands.size(); ++i)
        if (!sameKind(a.csgOperands[i], b.csgOperands[i]) || a.csgOperands[i].material != b.csgOperands[i].material ||
            (places && !samePlace(a.csgOperands[i], b.csgOperands[i])))
            return false;
    return true;
}

// The same primitives, meshes and csg objects; places: standing at the same places.
// samePrimitives: the primitives are known to be byte for byte the same.
bool sameGeometry(const Scene& a, const Scene& b, bool places, bool samePrimitives) {
    if (a.primitives.size() != b.primitives.size() || a.meshes.size() != b.meshes.size()) return false;
    for (size_t i = 0; i < a.primitives.size() && !samePrimitives; ++i)
        if (!sameKind(a.primitives[i], b.primitives[i]) || (places && !samePlace(a.primitives[i], b.primitives[i])))
            return false;
    for (size_t i = 0; i < a.meshes.size(); ++i)
        if (!sameMesh(a.meshes[i], b.meshes[i])) return false;
    return sameCsg(a, b, places);
}

bool sameMaterial(const Material& a, const Material& b) {
    auto sameMap = [](const TextureMap& x, const TextureMap& y) {
        return x.image == y.image && x.repeatU == y.repeatU && x.repeatV == y.repeatV;
    };
    return a.diffuse == b.diffuse && a.ambient == b.ambient && a.specular == b.specular &&
           a.reflective == b.reflective && a.transparent == b.transparent && a.emissive == b.emissive &&
           a.shininess == b.shininess && a.ior == b.ior && a.blend == b.blend && sameMap(a.texture, b.texture) &&
           sameMap(a.bumpMap, b.bumpMap);
}

bool sameLight(const Light& a, const Light& b) {
    return a.type == b.type && a.color == b.color && a.attenuation == b.attenuation && a.position == b.position &&
           a.direction == b.direction && a.angleDegrees == b.angleDegrees &&
           a.penumbraDegrees == b.penumbraDegrees && a.radius == b.radius && a.width == b.width &&
           a.height == b.height;
}

template <class T, class Same>
bool sameAll(const std::vector<T>& a, const std::vector<T>& b, Same same) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (!same(a[i], b[i])) return false;
    return true;
}

// `scene` with the images its materials use and the meshes its instances use alone, each
// numbered in the order it is first used.
Scene usedResourcesOnly(const Scene& scene) {
    Scene used = scene;
    used.images.clear();
    used.imageFiles.clear();
    std::vector<int> imageIndex(scene.images.size(), -1);
    auto renumberImage = [&](int& image) {
        if (image < 0 || size_t(image) >= scene.images.size()) return;
        int& index = imageIndex[size_t(image)];
        if (index < 0) {
            index = int(used.images.size());
            used.images.push_back(scene.images[size_t(image)]);
        }
        image = index;
    };
    for (Material& m : used.materials) {
        renumberImage(m.texture.image);
        renumberImage(m.bumpMap.image);
    }
    used.meshes.clear();
    used.meshFiles.clear();
    std::vector<int> meshIndex(scene.meshes.size(), -1);
    for (auto* list : {&used.primitives, &used.csgOperands})
        for (PrimitiveInstance& instance : *list) {
            if (instance.mesh < 0 || size_t(instance.mesh) >= scene.meshes.size()) continue;
            int& index = meshIndex[size_t(instance.mesh)];
            if (index < 0) {
                index = int(used.meshes.size());
                used.meshes.push_back(scene.meshes[size_t(instance.mesh)]);
            }
            instance.mesh = index;
        }
    return used;
}

}  // namespace

SceneDifference compareRendered(const Scene& a, const Scene& b) {
    SceneDifference d = compareScenes(usedResourcesOnly(a), usedResourcesOnly(b));
    d.camera = false;
    return d;
}

SceneDifference compareScenes(const Scene& a, const Scene& b) {
    SceneDifference d;
    // The common case first, at memcmp's speed (a frame after no edit, or after a material
    // or light edit, of a scene of millions of instances): byte for byte the same
    // instances. Bytes that differ (a -0 for a 0, padding) fall back to field by field.
    const bool samePrimitives = sameBytes(a.primitives, b.primitives);
    d.geometry = !sameGeometry(a, b, true, samePrimitives);
    d.transformsOnly = d.geometry && sameGeometry(a, b, false, false);
    if (!samePrimitives && (!d.geometry || d.transformsOnly))
        for (size_t i = 0; i < a.primitives.size() && !d.primitiveMaterials; ++i)
            d.primitiveMaterials = a.primitives[i].material != b.primitives[i].material;
    d.materials = !sameAll(a.materials, b.materials, sameMaterial);
    d.lights = !sameAll(a.lights, b.lights, sameLight);
    d.images = !sameAll(a.images, b.images, [](const Image& x, const Image& y) {
        return x.width == y.width && x.height == y.height && sameBytes(x.rgb, y.rgb);
    });
    d.globals = a.globals.ka != b.globals.ka || a.globals.kd != b.globals.kd || a.globals.ks != b.globals.ks ||
                a.globals.kt != b.globals.kt;
    d.camera = !(a.camera == b.camera);
    return d;
}

}  // namespace ray
