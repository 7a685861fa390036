// Looking up a texture's color at texture coordinates (SPEC §5).
//
// A texture is tiled repeatU × repeatV times over the surface: s = fract(u·repeatU),
// t = fract(v·repeatV), with t = 0 at the bottom of the image (row 0 is its top).
#pragma once

#include "image/image.h"
#include "render/render_settings.h"

namespace ray {

// The texel the course picks: column floor(s·width), row floor((1 − t)·height), each
// clamped into the image (t = 0 would otherwise name the row below the last).
Vec3 sampleNearest(const Image& texture, double u, double v, double repeatU, double repeatV);

// Bilinear interpolation between the four texels around (s·width, (1 − t)·height), with
// texel centres at half-integer positions. Neighbours beyond an edge wrap around to the
// other side, as the texture itself repeats across the surface.
Vec3 sampleBilinear(const Image& texture, double u, double v, double repeatU, double repeatV);

// The course's bilinear filter (SPEC §5, --texture-filter course): the same interpolation
// with texel corners at integer positions, i.e. without the half-texel shift, so texel
// (i, j) is weighted fully at (i, j) and the image appears shifted by half a texel.
Vec3 sampleCourseBilinear(const Image& texture, double u, double v, double repeatU, double repeatV);

// Dispatches on the filter. Trilinear (mipmapped) filtering needs the footprint of the
// ray on the surface, which a single ray does not have: it samples bilinearly here.
Vec3 sampleTexture(const Image& texture, double u, double v, double repeatU, double repeatV, TextureFilter filter);

}  // namespace ray
