#include "render/texture_footprint.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "scene/mesh.h"

namespace ray {

double pixelSpreadAngle(double heightAngleDegrees, int imageHeight) {
    return 2 * std::tan(radians(heightAngleDegrees) / 2) / double(std::max(1, imageHeight));
}

double primitiveUvDensity(PrimitiveType type) {
    switch (type) {
        case PrimitiveType::Sphere: return 2 / std::numbers::pi;  // v: half a circle of radius 1/2
        case PrimitiveType::Torus: return 4 / std::numbers::pi;   // v: a circle of radius 1/8
        default: return 1;                                         // faces, sides and caps of unit size
    }
}

double meshUvDensity(const TriangleMesh& mesh) {
    double uvArea = 0, objectArea = 0;
    for (size_t i = 0; i < mesh.triangles.size(); ++i) {
        const auto& t = mesh.triangles[i];
        objectArea += length(cross(mesh.corner(i, 1) - mesh.corner(i, 0), mesh.corner(i, 2) - mesh.corner(i, 0))) / 2;
        if (t[0].texCoord < 0 || t[1].texCoord < 0 || t[2].texCoord < 0) continue;
        const auto& a = mesh.texCoords[size_t(t[0].texCoord)];
        const auto& b = mesh.texCoords[size_t(t[1].texCoord)];
        const auto& c = mesh.texCoords[size_t(t[2].texCoord)];
        uvArea += std::abs((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])) / 2;
    }
    if (uvArea <= 0 || objectArea <= 0) return 1;
    return std::sqrt(uvArea / objectArea);
}

}  // namespace ray
