// Trilinear texture filtering: mipmaps and the footprint of a ray on a surface.
//
// Mipmaps are built as image/mipmap.h describes (the kernel reads the same levels).
//
// The footprint: a documented approximation instead of ray differentials ("ray cones"
// without curvature). A camera ray spreads by the pixel spread angle
//     α = 2·tan(heightAngle/2) / imageHeight   (radians per pixel, the course's camera),
// so at distance t along a unit ray it covers W = α·t of world space across, stretched to
// W / cos θ across the surface it meets (θ between the ray and the shading normal; cos θ
// is clamped to ≥ kMinFootprintCos so grazing hits pick the coarsest level rather than
// dividing by zero). t is the length of the ray's own segment: a reflected or refracted
// ray starts a new cone at its surface (footprints after a bounce are underestimated, i.e.
// sharper, never blurrier). World length becomes object length by the largest stretch of
// worldToObject within the tangent plane (the square root of the largest eigenvalue of
// the 2×2 Gram matrix of M·t1, M·t2 for any orthonormal tangents t1, t2: basis-free), and
// object length becomes texture coordinates by the primitive's UV density (uv units per
// object unit: render/texture_footprint.h, which the kernel's packing uses too).
// The level is λ = log2(footprintUv · max(repeatU·width, repeatV·height)) clamped to
// [0, levels − 1] (the larger axis: isotropic filtering errs towards blur, not aliasing);
// the color is the bilinear sample of level ⌊λ⌋ mixed with that of level ⌊λ⌋ + 1 by the
// fraction of λ. Antialiasing samples all use the pixel's footprint.
//
// cl/shading/texture_filter.cl is the same computation in float.
#pragma once

#include "core/math.h"
#include "image/mipmap.h"
#include "render/texture_footprint.h"
#include "scene/scene.h"

namespace ray {

constexpr double kMinFootprintCos = 0.01;

// The width of a hit's footprint in texture coordinates (before the material's repeats).
double textureFootprint(double spreadAngle, double distance, const Vec3& rayDirection, const Vec3& worldNormal,
                        const Affine& worldToObject, double uvDensity);

// λ, clamped to [0, levelCount − 1].
double mipLevel(double footprintUv, int width, int height, double repeatU, double repeatV, int levelCount);

Vec3 sampleTrilinear(const MipPyramid& pyramid, double u, double v, double repeatU, double repeatV,
                     double footprintUv);

}  // namespace ray
