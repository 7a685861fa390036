#include "scene/scene_changes.h"

#include <atomic>

namespace ray {

SceneChanges& SceneChanges::operator|=(const SceneChanges& other) {
    const bool refitOnly = (!geometry || transformsOnly) && (!other.geometry || other.transformsOnly);
    geometry = geometry || other.geometry;
    transformsOnly = geometry && refitOnly;
    primitiveMaterials = primitiveMaterials || other.primitiveMaterials;
    materials = materials || other.materials;
    lights = lights || other.lights;
    images = images || other.images;
    globals = globals || other.globals;
    camera = camera || other.camera;
    return *this;
}

bool SceneChanges::covers(const SceneChanges& other) const {
    const bool geometryCovered = !other.geometry || (geometry && (!transformsOnly || other.transformsOnly));
    return geometryCovered && (primitiveMaterials || !other.primitiveMaterials) && (materials || !other.materials) &&
           (lights || !other.lights) && (images || !other.images) && (globals || !other.globals) &&
           (camera || !other.camera);
}

std::vector<std::string> SceneChanges::names() const {
    std::vector<std::string> parts;
    if (geometry) parts.push_back(transformsOnly ? "transforms" : "geometry");
    if (primitiveMaterials) parts.push_back("primitives");
    if (materials) parts.push_back("materials");
    if (lights) parts.push_back("lights");
    if (images) parts.push_back("textures");
    if (globals) parts.push_back("globals");
    if (camera) parts.push_back("camera");
    return parts;
}

uint64_t SceneLineage::fresh() {
    static std::atomic<uint64_t> last{0};
    return ++last;
}

SceneLineage SceneLineage::after(const SceneLineage& before, const SceneChanges& changes) {
    SceneChanges beyondCamera = changes;
    beyondCamera.camera = false;
    if (!beyondCamera.any()) return before;  // renderers take each frame's camera from their caller
    SceneLineage next;
    next.revision = fresh();
    const size_t keep = before.steps.size() < kMaxSteps ? before.steps.size() : kMaxSteps - 1;
    next.steps.assign(before.steps.end() - std::ptrdiff_t(keep), before.steps.end());
    next.steps.push_back({before.revision, changes});
    return next;
}

std::optional<SceneChanges> SceneLineage::changesSince(uint64_t since) const {
    if (since == 0) return std::nullopt;
    if (since == revision) return SceneChanges{};
    SceneChanges total;
    for (size_t i = steps.size(); i-- > 0;) {
        total |= steps[i].changes;
        if (steps[i].from == since) return total;
    }
    return std::nullopt;
}

}  // namespace ray
