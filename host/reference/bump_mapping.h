// Bump mapping (SPEC §1 `bumpmap file u v`): the map's gray level is a height field over the
// surface's texture coordinates, and its slope tilts the shading normal.
//
// Scale convention: with h ∈ [0, 1] the map's gray level (the mean of R, G, B), read
// bilinearly and differentiated by central differences one texel apart, the object-space
// normal becomes N' = normalize(N − kBumpStrength·(∂h/∂s·T + ∂h/∂t·B)), where the
// derivatives are per texel (of the map as repeated on the surface), T is the unit
// direction of increasing u in the tangent plane and B = N × T that of increasing v (−N × T
// on mesh triangles whose texture coordinates are mirrored: ShapeHit::bitangentSign). A gray
// ramp rising by 0.5 per texel tilts the normal by 45°; brighter is higher. The kernel does
// the same in float (cl/shading/bump.cl). Bump maps follow the textures switch (--no-textures).
#pragma once

#include "image/image.h"
#include "core/math.h"
#include "scene/scene.h"

namespace ray {

constexpr double kBumpStrength = 2.0;

// The height's slope per texel along s (u) and t (v) at (u, v) with the map's repeats.
struct HeightSlope {
    double alongU = 0, alongV = 0;
};
HeightSlope heightSlope(const Image& map, double u, double v, double repeatU, double repeatV);

// The object-space direction in which u grows (SPEC §5), before it is made orthogonal to
// the normal: from the cube face or cap the normal names, around the y axis for the
// sphere, the sides of the cylinder and cone, and the torus. Meshes give their own
// (ShapeHit::tangent). Zero where there is none.
Vec3 objectTangent(PrimitiveType type, const Vec3& objectPoint, const Vec3& objectNormal);

// N' of the convention above (N unit length, object space); N itself where the tangent is
// degenerate.
Vec3 bumpedNormal(const Vec3& normal, const Vec3& tangent, const HeightSlope& slope, double bitangentSign = 1);

}  // namespace ray
