// Refraction and area-light sampling for the reference renderer: the same steps as the
// kernel's cl/shading/optics.cl, in double precision, so that both renderers trace the same rays
// and draw the same area-light samples.
#pragma once

#include <array>
#include <cstdint>

#include "core/math.h"
#include "render/render_settings.h"
#include "scene/scene.h"

namespace ray {

// The media a ray travels through, innermost last (cl/shading/optics.cl MediumStack): the ior of
// each transparent object it is inside of; air (1) outside them all. Entering a surface
// pushes the material's ior, leaving pops; at most kMaxMedia levels are kept (entering a
// fifth nested object overwrites the innermost entry).
struct MediumStack {
    static constexpr int kMaxMedia = 4;
    std::array<double, kMaxMedia> ior{};
    int count = 0;

    double current() const { return count > 0 ? ior[size_t(count - 1)] : 1.0; }
    // The ior on the near side of a surface: the current medium, or the object's own for
    // a ray leaving an object that no entry recorded (a camera inside it).
    double before(bool entering, double materialIor) const {
        return (entering || count > 0) ? current() : materialIor;
    }
    // The stack the transmitted ray carries beyond the surface.
    MediumStack beyond(bool entering, double materialIor) const;
};

// Snell's law for unit direction d meeting a surface whose unit normal n faces the ray,
// from ior n1 into ior n2; false for total internal reflection.
bool refractDirection(const Vec3& d, const Vec3& n, double n1, double n2, Vec3& transmitted);

// The exact Fresnel reflectance of a dielectric interface for unpolarised light (the mean
// of the s and p reflectances), met at cosIncident = −d·n from ior n1 into ior n2: the
// share of the light that the surface reflects, 1 − R being what it transmits. 1 under
// total internal reflection (by refractDirection's test, so the two always agree) and at
// grazing incidence; ((n1 − n2)/(n1 + n2))² head on; 0 where n1 = n2. A negative
// cosIncident (a bump map tilting the shading normal past the ray) counts as its
// magnitude. cl/shading/optics.cl fresnelReflectance is the same steps in float (--fresnel, SPEC §4).
double fresnelReflectance(double cosIncident, double n1, double n2);

// The random dimensions of area-light samples (host/core/random.h): cell `cell` of light
// `light` is jittered by dimensions areaLightDimension(light, cell, 0 for u / 1 for v).
constexpr uint32_t kAreaDimensionBase = 16;
constexpr uint32_t kMaxAreaCells = 1024;  // at most 32 × 32 samples per area light
constexpr uint32_t areaLightDimension(uint32_t light, uint32_t cell, uint32_t axis) {
    return kAreaDimensionBase + 2 * (light * kMaxAreaCells + cell) + axis;
}

// The point of the area light's rectangle for grid cell `cell` of a side × side grid, as
// cl/shading/optics.cl areaLightPoint: width along U = normalize(helper × d), height along
// V = d × U, helper = +y, or +z when |d.y| > 0.99.
Vec3 areaLightPoint(const Light& light, int lightIndex, int cell, int side, uint32_t pixel, uint32_t sample,
                    uint32_t seed);

}  // namespace ray
