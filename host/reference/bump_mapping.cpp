#include "reference/bump_mapping.h"

#include <cmath>

#include "reference/texture_sampling.h"

namespace ray {

namespace {

double height(const Image& map, double u, double v, double repeatU, double repeatV) {
    Vec3 c = sampleBilinear(map, u, v, repeatU, repeatV);
    return (c.x + c.y + c.z) / 3;
}

}  // namespace

HeightSlope heightSlope(const Image& map, double u, double v, double repeatU, double repeatV) {
    // One texel of the repeated map, in u and v.
    double du = 1 / (map.width * repeatU), dv = 1 / (map.height * repeatV);
    return {(height(map, u + du, v, repeatU, repeatV) - height(map, u - du, v, repeatU, repeatV)) / 2,
            (height(map, u, v + dv, repeatU, repeatV) - height(map, u, v - dv, repeatU, repeatV)) / 2};
}

Vec3 objectTangent(PrimitiveType type, const Vec3& p, const Vec3& n) {
    // Cube faces and caps: the face mappings of SPEC §5 (u = x + 0.5 on ±y, +z; 0.5 − z on
    // +x; z + 0.5 on −x; 0.5 − x on −z).
    bool flat = type == PrimitiveType::Cube ||
                ((type == PrimitiveType::Cylinder || type == PrimitiveType::Cone) && std::abs(n.y) == 1);
    if (flat) {
        if (n.x > 0.5) return {0, 0, -1};
        if (n.x < -0.5) return {0, 0, 1};
        if (n.z < -0.5) return {-1, 0, 0};
        return {1, 0, 0};
    }
    if (type == PrimitiveType::Mesh) return {};
    // u = atan2(−z, x)/2π grows along (z, 0, −x).
    return {p.z, 0, -p.x};
}

Vec3 bumpedNormal(const Vec3& normal, const Vec3& tangent, const HeightSlope& slope, double bitangentSign) {
    Vec3 t = tangent - dot(tangent, normal) * normal;
    double len = length(t);
    if (!(len > 1e-12)) return normal;
    t = t / len;
    Vec3 b = bitangentSign * cross(normal, t);
    Vec3 bumped = normal - kBumpStrength * (slope.alongU * t + slope.alongV * b);
    return normalize(bumped);
}

}  // namespace ray
