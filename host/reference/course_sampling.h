// Where in a pixel the renderers take their samples, and how the samples become the
// pixel's color (SPEC §3). Free of ray tracing: the caller supplies the color of a sample
// at offsets (sx, sy) ∈ [0, 1)² within the pixel (x to the right, y down), and any
// renderer can reuse these patterns.
#pragma once

#include <cstdint>
#include <functional>

#include "core/math.h"
#include "render/render_settings.h"

namespace ray {

// The color seen through offset (sx, sy) of the pixel.
using PixelSampleFunction = std::function<Vec3(double sx, double sy)>;

// --aa off: one sample at the pixel centre, returned as it is.
Vec3 sampleCenter(const PixelSampleFunction& sample);

// Counts for the tests: how many samples were traced, and how many of them make up the
// pixel (a subdivided square's own four samples are traced and then replaced).
struct CourseSampleCount {
    int traced = 0;  // 4, 4 + 16, … at most 4 + 16 + 64
    int used = 0;    // 4 to 64
};

// --aa course: value(pixel, 1), where value(square, level) takes the four samples at the
// centres of the square's quadrants, each clamped to [0, 1] per channel; if level < 3, each
// quadrant whose sample differs from a horizontal or vertical neighbour's (top-left and
// top-right, bottom-left and bottom-right, top-left and bottom-left, top-right and
// bottom-right; not the diagonals) by more than kCourseAaContrast = 50/255 in some channel has
// its sample replaced by value(quadrant, level + 1); the result is the mean of the four.
// Deterministic; the result is in [0, 1].
Vec3 sampleCourse(const PixelSampleFunction& sample, CourseSampleCount* count = nullptr);

// --aa stratified: one sample jittered within each cell of a k×k grid, k = floor(√samples)
// (a count that is not a square is rounded down to one). Cell c (row c / k, column c % k)
// is jittered by sampleRandom(pixel, c, 0 for x / 1 for y, seed) (random.h), exactly as the
// kernel does, then warped through the tent filter's inverse distribution (rayTentOffset in
// cl/random.h: a tent of radius one pixel, by filter importance sampling, so the offsets
// span (-0.5, 1.5)). Samples are clamped to [0, 1] per channel, as the course mode does,
// and averaged with equal weights.
Vec3 sampleStratified(const PixelSampleFunction& sample, int samples, uint32_t pixelIndex, uint32_t seed);

// k = floor(√samples), at least 1.
int stratifiedGridSide(int samples);
// The offsets of stratified sample `index` in a k×k grid (as sampleStratified).
void stratifiedOffset(int index, int side, uint32_t pixelIndex, uint32_t seed, double& sx, double& sy);

// --aa adaptive: a first pass of 2×2 jittered samples (sample numbers 0..3); where they
// spread by more than kAdaptiveContrast (max − min in the channel where that is largest,
// after clamping to [0, 1]), a second pass adds a k×k jittered grid, k = floor(√samples),
// with sample numbers 4.. (its cell c jittered by sampleRandom(pixel, 4 + c, 0 / 1, seed)).
// Offsets go through the tent filter as in stratified sampling. The pixel is the mean of
// every sample taken: 4 samples in flat regions,
// 4 + k² at edges, in shadow penumbras and wherever area lights, depth of field or motion
// blur make the first four disagree. With samples ≤ 4 it is plain stratified sampling.
Vec3 sampleAdaptive(const PixelSampleFunction& sample, int samples, uint32_t pixelIndex, uint32_t seed,
                    int* taken = nullptr);

// Dispatches on settings.antialias. pixelIndex = y·width + x names the pixel for the
// stochastic modes.
Vec3 samplePixel(const RenderSettings& settings, uint32_t pixelIndex, const PixelSampleFunction& sample);

}  // namespace ray
