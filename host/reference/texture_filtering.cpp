#include "reference/texture_filtering.h"

#include <algorithm>
#include <cmath>

#include "reference/texture_sampling.h"

namespace ray {

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
