// Trilinear texture filtering: mipmaps and the footprint of a ray on a surface.
//
// Mipmaps. Level 0 is the image; level k+1 halves level k (width and height rounded down,
// never below 1) by a box filter: texel (x, y) is the mean of texels 2x..2x+1, 2y..2y+1
// of level k, the second column or row clamped into the image (so an odd size drops its
// last column or row, and a 1-wide level keeps averaging rows only). Every level is
// rounded to 8 bits, v = round(255·mean)/255, because the kernel keeps its levels in the
// same RGBA8 texel buffer as the images; both renderers therefore read identical values.
// The kernel stores a texture's levels back to back from RayTexture.info.x, their count
// in info.w (cl/shared_types.h); level k is max(1, width >> k) × max(1, height >> k).
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
// object unit, the largest rate over the surface, ignoring the poles of the sphere):
//     cube, cylinder, cone 1; sphere 2/π; torus 4/π (v around the tube of radius 1/8);
//     mesh sqrt(Σ uv area / Σ object area) over its triangles (1 without vt).
// The level is λ = log2(footprintUv · max(repeatU·width, repeatV·height)) clamped to
// [0, levels − 1] (the larger axis: isotropic filtering errs towards blur, not aliasing);
// the color is the bilinear sample of level ⌊λ⌋ mixed with that of level ⌊λ⌋ + 1 by the
// fraction of λ. Antialiasing samples all use the pixel's footprint.
//
// cl/texture_filter.cl is the same computation in float.
#pragma once

#include <vector>

#include "image/image.h"
#include "core/math.h"
#include "scene/scene.h"

namespace ray {

struct TriangleMesh;

constexpr double kMinFootprintCos = 0.01;

// Levels 1, 2, … of the image's mipmap (level 0 is the image itself), to 1×1.
std::vector<Image> buildMipLevels(const Image& base);

// The image and its levels, for the reference renderer.
struct MipPyramid {
    std::vector<Image> levels;  // levels[0] is the image
};
MipPyramid buildMipPyramid(const Image& base);

// α: radians of view per pixel row.
double pixelSpreadAngle(double heightAngleDegrees, int imageHeight);

// Texture coordinate units per object-space unit (see above).
double primitiveUvDensity(PrimitiveType type);
double meshUvDensity(const TriangleMesh& mesh);

// The width of a hit's footprint in texture coordinates (before the material's repeats).
double textureFootprint(double spreadAngle, double distance, const Vec3& rayDirection, const Vec3& worldNormal,
                        const Affine& worldToObject, double uvDensity);

// λ, clamped to [0, levelCount − 1].
double mipLevel(double footprintUv, int width, int height, double repeatU, double repeatV, int levelCount);

Vec3 sampleTrilinear(const MipPyramid& pyramid, double u, double v, double repeatU, double repeatV,
                     double footprintUv);

}  // namespace ray
