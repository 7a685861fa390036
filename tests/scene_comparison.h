// Bit-for-bit comparisons of flattened scenes, for the tests of the document and its
// saving: a saved file must load back to the very scene that was saved.
#pragma once

#include <cstring>
#include <vector>

#include "scene/scene.h"

namespace ray::test {

// Bit-for-bit equality of two transforms (NaNs and signed zeros included).
inline bool sameBits(const Affine& a, const Affine& b) { return std::memcmp(a.m, b.m, sizeof a.m) == 0; }

enum class IdsToo { Yes, No };

// The instances, bit for bit; with IdsToo::No, whatever objects they come from.
inline bool sameInstances(const std::vector<PrimitiveInstance>& a, const std::vector<PrimitiveInstance>& b,
                          IdsToo ids = IdsToo::Yes) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i) {
        const PrimitiveInstance &p = a[i], &q = b[i];
        if (!sameBits(p.objectToWorld, q.objectToWorld) || !sameBits(p.worldToObject, q.worldToObject) ||
            p.type != q.type || p.material != q.material || p.mesh != q.mesh || p.csg != q.csg ||
            p.motion != q.motion || (ids == IdsToo::Yes && p.sourceObject != q.sourceObject))
            return false;
    }
    return true;
}

// Bit-for-bit equality of doubles, field by field (the structs' padding is not compared).
inline bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
inline bool same(const Vec3& a, const Vec3& b) { return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z); }
inline bool same(const TextureMap& a, const TextureMap& b) {
    return a.image == b.image && same(a.repeatU, b.repeatU) && same(a.repeatV, b.repeatV);
}
inline bool same(const Material& a, const Material& b) {
    return same(a.diffuse, b.diffuse) && same(a.ambient, b.ambient) && same(a.specular, b.specular) &&
           same(a.reflective, b.reflective) && same(a.transparent, b.transparent) && same(a.emissive, b.emissive) &&
           same(a.shininess, b.shininess) && same(a.ior, b.ior) && same(a.blend, b.blend) &&
           same(a.texture, b.texture) && same(a.bumpMap, b.bumpMap);
}
inline bool same(const Light& a, const Light& b) {
    return a.type == b.type && same(a.color, b.color) && same(a.attenuation, b.attenuation) &&
           same(a.position, b.position) && same(a.direction, b.direction) && same(a.angleDegrees, b.angleDegrees) &&
           same(a.penumbraDegrees, b.penumbraDegrees) && same(a.radius, b.radius) && same(a.width, b.width) &&
           same(a.height, b.height);
}
template <class T>
inline bool sameAll(const std::vector<T>& a, const std::vector<T>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (!same(a[i], b[i])) return false;
    return true;
}

// The materials, lights, camera, globals and csg programs, bit for bit.
inline bool sameTables(const Scene& a, const Scene& b) {
    bool csg = a.csgObjects.size() == b.csgObjects.size();
    for (size_t i = 0; csg && i < a.csgObjects.size(); ++i) {
        const auto &p = a.csgObjects[i].program, &q = b.csgObjects[i].program;
        csg = p.size() == q.size();
        for (size_t k = 0; csg && k < p.size(); ++k) csg = p[k].kind == q[k].kind && p[k].operand == q[k].operand;
    }
    const Camera &c = a.camera, &d = b.camera;
    const bool camera = same(c.position, d.position) && same(c.look, d.look) && same(c.up, d.up) &&
                        same(c.heightAngleDegrees, d.heightAngleDegrees) && same(c.aperture, d.aperture) &&
                        same(c.focalLength, d.focalLength);
    const GlobalCoefficients &g = a.globals, &h = b.globals;
    const bool globals = same(g.ka, h.ka) && same(g.kd, h.kd) && same(g.ks, h.ks) && same(g.kt, h.kt);
    return csg && camera && globals && sameAll(a.materials, b.materials) && sameAll(a.lights, b.lights) &&
           a.meshFiles.size() == b.meshFiles.size();
}

}  // namespace ray::test
