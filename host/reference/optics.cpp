#include "reference/optics.h"

#include <algorithm>
#include <cmath>

#include "core/random.h"

namespace ray {

int areaLightGridSide(const RenderSettings& settings) {
    int side = std::max(1, int(std::sqrt(double(settings.areaSamples))));
    while ((side + 1) * (side + 1) <= settings.areaSamples) ++side;  // in case sqrt rounds down
    return side;
}

MediumStack MediumStack::beyond(bool entering, double materialIor) const {
    MediumStack next = *this;
    if (entering) {
        if (next.count < kMaxMedia) ++next.count;
        next.ior[size_t(next.count - 1)] = materialIor;
    } else if (next.count > 0) {
        --next.count;
    }
    return next;
}

bool refractDirection(const Vec3& d, const Vec3& n, double n1, double n2, Vec3& transmitted) {
    double eta = n1 / n2;
    double cosIncident = -dot(d, n);
    double k = 1 - eta * eta * (1 - cosIncident * cosIncident);
    if (k < 0) return false;
    transmitted = normalize(eta * d + (eta * cosIncident - std::sqrt(k)) * n);
    return true;
}

double fresnelReflectance(double cosIncident, double n1, double n2) {
    if (n1 == n2) return 0;  // no interface: the ray goes straight on
    double eta = n1 / n2;
    double cosI = std::abs(cosIncident);
    double k = 1 - eta * eta * (1 - cosI * cosI);  // cos²θt, as refractDirection computes it
    if (k < 0) return 1;                            // total internal reflection
    double cosT = std::sqrt(k);
    double s = (n1 * cosI - n2 * cosT) / (n1 * cosI + n2 * cosT);
    double p = (n2 * cosI - n1 * cosT) / (n2 * cosI + n1 * cosT);
    double r = 0.5 * (s * s + p * p);
    return r <= 1 ? r : 1;  // an ior ≤ 0 (the loader takes any number) gives NaN or more than 1
}

Vec3 areaLightPoint(const Light& light, int lightIndex, int cell, int side, uint32_t pixel, uint32_t sample,
                    uint32_t seed) {
    Vec3 d = normalize(light.direction);
    Vec3 helper = std::abs(d.y) > 0.99 ? Vec3{0, 0, 1} : Vec3{0, 1, 0};
    Vec3 u = normalize(cross(helper, d));
    Vec3 v = cross(d, u);
    double jx = sampleRandom(pixel, sample, areaLightDimension(uint32_t(lightIndex), uint32_t(cell), 0), seed);
    double jy = sampleRandom(pixel, sample, areaLightDimension(uint32_t(lightIndex), uint32_t(cell), 1), seed);
    double a = (cell % side + jx) / side - 0.5;
    double b = (cell / side + jy) / side - 0.5;
    return light.position + a * light.width * u + b * light.height * v;
}

}  // namespace ray
