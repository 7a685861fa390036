#include "reference/texture_filtering.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "scene/mesh.h"
#include "reference/texture_sampling.h"

namespace ray {

namespace {

// The 8-bit value the kernel's texel buffer holds for a channel (as packTextures rounds).
double eightBit(double c) { return double(std::lround(std::clamp(c, 0.0, 1.0) * 255.0)); }

Image halve(const Image& source) {
    Image level(std::max(1, source.width / 2), std::max(1, source.height / 2));
    for (int y = 0; y < level.height; ++y) {
        int y0 = std::min(2 * y, source.height - 1), y1 = std::min(2 * y + 1, source.height - 1);
        for (int x = 0; x < level.width; ++x) {
            int x0 = std::min(2 * x, source.width - 1), x1 = std::min(2 * x + 1, source.width - 1);
            Vec3 sum;
            for (Vec3 c : {source.at(x0, y0), source.at(x1, y0), source.at(x0, y1), source.at(x1, y1)})
                sum += Vec3{eightBit(c.x), eightBit(c.y), eightBit(c.z)};
            // Round the mean of the four 8-bit values back to 8 bits.
            level.set(x, y, Vec3{std::round(sum.x / 4), std::round(sum.y / 4), std::round(sum.z / 4)} / 255.0);
        }
    }
    return level;
}

}  // namespace

std::vector<Image> buildMipLevels(const Image& base) {
    std::vector<Image> levels;
    const Image* previous = &base;
    while (previous->width > 1 || previous->height > 1) {
        levels.push_back(halve(*previous));
        previous = &levels.back();
    }
    return levels;
}

MipPyramid buildMipPyramid(const Image& base) {
    MipPyramid pyramid;
    pyramid.levels.push_back(base);
    for (Image& level : buildMipLevels(base)) pyramid.levels.push_back(std::move(level));
    return pyramid;
}

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

double textureFootprint(double spreadAngle, double distance, const Vec3& rayDirection, const Vec3& worldNormal,
                        const Affine& worldToObject, double uvDensity) {
    double cosTheta = std::max(std::abs(dot(rayDirection, worldNormal)), kMinFootprintCos);
    // Orthonormal tangents; the Gram matrix's eigenvalues do not depend on which.
    Vec3 helper = std::abs(worldNormal.x) < 0.5 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    Vec3 t1 = normalize(cross(worldNormal, helper));
    Vec3 t2 = cross(worldNormal, t1);
    Vec3 a = worldToObject.transformVector(t1), b = worldToObject.transformVector(t2);
    double aa = dot(a, a), bb = dot(b, b), ab = dot(a, b);
    double largest = 0.5 * (aa + bb + std::sqrt((aa - bb) * (aa - bb) + 4 * ab * ab));
    return spreadAngle * distance / cosTheta * std::sqrt(largest) * uvDensity;
}

double mipLevel(double footprintUv, int width, int height, double repeatU, double repeatV, int levelCount) {
    double texels = footprintUv * std::max(repeatU * width, repeatV * height);
    double level = std::log2(std::max(texels, 1e-30));
    return std::clamp(level, 0.0, double(std::max(0, levelCount - 1)));
}

Vec3 sampleTrilinear(const MipPyramid& pyramid, double u, double v, double repeatU, double repeatV,
                     double footprintUv) {
    const Image& base = pyramid.levels[0];
    int count = int(pyramid.levels.size());
    double level = mipLevel(footprintUv, base.width, base.height, repeatU, repeatV, count);
    int lower = std::min(int(level), count - 1), upper = std::min(lower + 1, count - 1);
    double fraction = level - lower;
    Vec3 fine = sampleBilinear(pyramid.levels[size_t(lower)], u, v, repeatU, repeatV);
    if (fraction <= 0) return fine;
    Vec3 coarse = sampleBilinear(pyramid.levels[size_t(upper)], u, v, repeatU, repeatV);
    return (1 - fraction) * fine + fraction * coarse;
}

}  // namespace ray
