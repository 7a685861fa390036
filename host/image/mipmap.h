// Mipmaps, as both renderers build them (the reference's MipPyramid, the kernel's texel
// buffer: host/opencl/scene_packing.cpp).
//
// Level 0 is the image; level k+1 halves level k (width and height rounded down, never
// below 1) by a box filter: texel (x, y) is the mean of texels 2x..2x+1, 2y..2y+1 of level
// k, the second column or row clamped into the image (so an odd size drops its last column
// or row, and a 1-wide level keeps averaging rows only). Every level is rounded to 8 bits,
// v = round(255·mean)/255, because the kernel keeps its levels in the same RGBA8 texel
// buffer as the images; both renderers therefore read identical values. The kernel stores
// a texture's levels back to back from RayTexture.offset, their count in RayTexture.levels
// (cl/shared_types.h); level k is max(1, width >> k) × max(1, height >> k).
#pragma once

#include <vector>

#include "image/image.h"

namespace ray {

// Levels 1, 2, … of the image's mipmap (level 0 is the image itself), to 1×1.
std::vector<Image> buildMipLevels(const Image& base);

// The image and its levels, for the reference renderer.
struct MipPyramid {
    std::vector<Image> levels;  // levels[0] is the image
};
MipPyramid buildMipPyramid(const Image& base);

}  // namespace ray
