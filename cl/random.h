/* The counter-based random numbers of the stochastic features, shared by the host and the
 * kernel so that both draw bit-identical samples.
 *
 * A sample's number is a pure function of (pixel, sample, dimension, seed): no state is
 * carried between work-items or threads, so any device, any launch order and any tiling
 * give the same image for the same seed. The mixing function is the PCG-RXS-M-XS hash
 * ("Hash Functions for GPU Rendering", Jarzynski and Olano, JCGT 2020). Only 32-bit
 * unsigned arithmetic is used, which wraps identically in C++ and OpenCL C; the float is
 * built from the top 24 bits, so its conversion and scaling are exact. */
#ifndef RAY_RANDOM_H
#define RAY_RANDOM_H

#if defined(__OPENCL_VERSION__) || defined(__OPENCL_C_VERSION__)
#define RAY_U32 uint
/* static: in OpenCL C (C99) a plain inline function has no definition of its own to call
 * where a compiler chooses not to inline it. */
#define RAY_FN static inline
#else
#include <cmath>
#include <cstdint>
#define RAY_U32 uint32_t
#define RAY_FN inline
namespace ray {
#endif

RAY_FN RAY_U32 rayHash(RAY_U32 v) {
    RAY_U32 state = v * 747796405u + 2891336453u;
    RAY_U32 word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

/* A number in [0, 1) for one dimension of one sample of one pixel. */
RAY_FN float rayRandom(RAY_U32 pixel, RAY_U32 sample, RAY_U32 dimension, RAY_U32 seed) {
    RAY_U32 h = rayHash(seed ^ rayHash(dimension ^ rayHash(sample ^ rayHash(pixel))));
    return (float)(h >> 8) * (1.0f / 16777216.0f);
}

/* The reconstruction filter of the stochastic antialiasing modes: a tent of radius one
 * pixel around the pixel's centre, applied by filter importance sampling. A stratified
 * coordinate u ∈ [0, 1) is warped by the tent's inverse distribution function into an
 * offset in (-0.5, 1.5) (pixel units, 0.5 the centre), so samples are denser near the
 * centre, reach half into the neighbouring pixels, and all weigh the same: smoother edges
 * than a box filter, with no negative lobes to ring. Shared so that both renderers place
 * their samples identically. */
RAY_FN float rayTentOffset(float u) {
    float t = u < 0.5f ? sqrt(2.0f * u) - 1.0f : 1.0f - sqrt(2.0f - 2.0f * u);
    return 0.5f + t;
}

#if !defined(__OPENCL_VERSION__) && !defined(__OPENCL_C_VERSION__)
}  /* namespace ray */
#endif

#endif
