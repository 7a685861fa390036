// Counter-based random numbers for the host: the kernel's own functions (cl/random.h),
// so that the reference renderer and the kernel draw bit-identical samples.
//
// A random number is a pure function of (pixel, sample, dimension, seed): the PCG hash of
// each coordinate in turn, with 32-bit unsigned arithmetic only (it wraps the same way in
// C++ and OpenCL C), and the top 24 bits scaled by 2⁻²⁴, exact in float and double. There
// is no generator state, so thread count and launch order cannot change an image.
//
// Dimensions in use: 0 and 1, the x and y jitter of a stratified sample within its cell
// (--aa stratified and adaptive); 2 and 3, the lens position of a depth-of-field sample;
// 4, the shutter time of motion blur (t = shutter · value, render_settings.h); 16 + 2·(light·1024 + cell) + axis,
// the jitter of an area light's sample in cell `cell` of its grid along its width
// (axis 0) and height (axis 1) (optics.h areaLightDimension, cl/shading/optics.cl RAY_DIM_AREA).
// The "sample" coordinate is the camera sample's number within its pixel, in the order
// the sampling pattern takes them; every hit along that sample's ray tree reuses it.
#pragma once

#include <cstdint>

#include "../../cl/random.h"  // rayHash, rayRandom (the path names cl/: this file is random.h too)

namespace ray {

// rayRandom as a double: the same value, a multiple of 2⁻²⁴ in [0, 1).
inline double sampleRandom(uint32_t pixel, uint32_t sample, uint32_t dimension, uint32_t seed) {
    return double(rayRandom(pixel, sample, dimension, seed));
}

}  // namespace ray
