// The facts of trilinear filtering's footprint that both renderers share: how far a camera
// ray spreads and how many texture coordinates an object-space unit covers. The reference
// turns them into a footprint and a mipmap level (host/reference/texture_filtering.h, where
// the model is described); the kernel receives them packed (host/opencl/scene_packing.cpp)
// and does the same in float (cl/shading/texture_filter.cl).
#pragma once

#include "scene/scene.h"

namespace ray {

struct TriangleMesh;

// α: radians of view per pixel row, 2·tan(heightAngle/2) / imageHeight.
double pixelSpreadAngle(double heightAngleDegrees, int imageHeight);

// Texture coordinate units per object-space unit, the largest rate over the surface
// (ignoring the poles of the sphere): cube, cylinder, cone 1; sphere 2/π; torus 4/π (v
// around the tube of radius 1/8); a mesh sqrt(Σ uv area / Σ object area) over its
// triangles (1 without vt).
double primitiveUvDensity(PrimitiveType type);
double meshUvDensity(const TriangleMesh& mesh);

}  // namespace ray
