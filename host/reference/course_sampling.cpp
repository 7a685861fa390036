#include "reference/course_sampling.h"

#include <algorithm>
#include <cmath>

#include "core/random.h"

namespace ray {

namespace {

// The largest per-channel spread (max − min) of four colors.
double spread(const Vec3 (&colors)[4]) {
    Vec3 lo = colors[0], hi = colors[0];
    for (const Vec3& c : colors) {
        lo = componentMin(lo, c);
        hi = componentMax(hi, c);
    }
    return maxComponent(hi - lo);
}

// Whether two samples differ by more than kCourseAaContrast in some channel.
bool courseDiffers(const Vec3& a, const Vec3& b) {
    return maxComponent(componentMax(a - b, b - a)) > kCourseAaContrast;
}

// value(square, level) for the square with top-left corner (x, y) and side size: the
// course's rule (docs/conventions.md, "Antialiasing"). A quadrant is subdivided when its
// sample differs from a horizontal or vertical neighbour's (not the diagonal one's).
Vec3 courseValue(const PixelSampleFunction& sample, double x, double y, double size, int level,
                 CourseSampleCount& count) {
    // Quadrants in the order top-left, top-right, bottom-left, bottom-right.
    const double half = size / 2;
    const double quadrantX[4] = {x, x + half, x, x + half};
    const double quadrantY[4] = {y, y, y + half, y + half};

    Vec3 colors[4];
    for (int q = 0; q < 4; ++q) colors[q] = clamp01(sample(quadrantX[q] + half / 2, quadrantY[q] + half / 2));
    count.traced += 4;

    bool subdivide[4] = {false, false, false, false};
    if (level < kCourseAaMaxLevel) {
        static constexpr int kNeighbours[4][2] = {{0, 1}, {2, 3}, {0, 2}, {1, 3}};  // rows, then columns
        for (const auto& pair : kNeighbours) {
            if (courseDiffers(colors[pair[0]], colors[pair[1]])) subdivide[pair[0]] = subdivide[pair[1]] = true;
        }
    }
    for (int q = 0; q < 4; ++q) {
        if (subdivide[q])
            colors[q] = courseValue(sample, quadrantX[q], quadrantY[q], half, level + 1, count);
        else
            count.used += 1;
    }
    return (colors[0] + colors[1] + colors[2] + colors[3]) / 4.0;
}

}  // namespace

Vec3 sampleCenter(const PixelSampleFunction& sample) { return sample(0.5, 0.5); }

Vec3 sampleCourse(const PixelSampleFunction& sample, CourseSampleCount* count) {
    CourseSampleCount local;
    Vec3 color = courseValue(sample, 0, 0, 1, 1, local);
    if (count) *count = local;
    return color;
}

int stratifiedGridSide(int samples) {
    int side = std::max(1, int(std::sqrt(double(samples))));
    while ((side + 1) * (side + 1) <= samples) ++side;  // in case sqrt rounds down
    return side;
}

void stratifiedOffset(int index, int side, uint32_t pixelIndex, uint32_t seed, double& sx, double& sy) {
    sx = rayTentOffset(float((index % side + sampleRandom(pixelIndex, uint32_t(index), 0, seed)) / side));
    sy = rayTentOffset(float((index / side + sampleRandom(pixelIndex, uint32_t(index), 1, seed)) / side));
}

Vec3 sampleStratified(const PixelSampleFunction& sample, int samples, uint32_t pixelIndex, uint32_t seed) {
    const int side = stratifiedGridSide(samples);
    Vec3 sum;
    for (int i = 0; i < side * side; ++i) {
        double sx, sy;
        stratifiedOffset(i, side, pixelIndex, seed, sx, sy);
        sum += clamp01(sample(sx, sy));
    }
    return sum / double(side * side);
}

namespace {

// The offsets of the sample in cell `cell` of a side×side grid, jittered by the random
// numbers of sample number `number`.
void jitteredCell(int cell, int side, uint32_t number, uint32_t pixelIndex, uint32_t seed, double& sx, double& sy) {
    sx = rayTentOffset(float((cell % side + sampleRandom(pixelIndex, number, 0, seed)) / side));
    sy = rayTentOffset(float((cell / side + sampleRandom(pixelIndex, number, 1, seed)) / side));
}

}  // namespace

Vec3 sampleAdaptive(const PixelSampleFunction& sample, int samples, uint32_t pixelIndex, uint32_t seed, int* taken) {
    if (samples <= 4) {
        if (taken) *taken = stratifiedGridSide(samples) * stratifiedGridSide(samples);
        return sampleStratified(sample, samples, pixelIndex, seed);
    }
    Vec3 first[4];
    Vec3 sum;
    for (int c = 0; c < 4; ++c) {
        double sx, sy;
        jitteredCell(c, 2, uint32_t(c), pixelIndex, seed, sx, sy);
        first[c] = clamp01(sample(sx, sy));
        sum += first[c];
    }
    int count = 4;
    if (spread(first) > kAdaptiveContrast) {
        const int side = stratifiedGridSide(samples);
        for (int c = 0; c < side * side; ++c) {
            double sx, sy;
            jitteredCell(c, side, uint32_t(4 + c), pixelIndex, seed, sx, sy);
            sum += clamp01(sample(sx, sy));
        }
        count += side * side;
    }
    if (taken) *taken = count;
    return sum / double(count);
}

Vec3 samplePixel(const RenderSettings& settings, uint32_t pixelIndex, const PixelSampleFunction& sample) {
    switch (settings.antialias) {
        case AntialiasMode::Off: return sampleCenter(sample);
        case AntialiasMode::Course: return sampleCourse(sample);
        case AntialiasMode::Stratified: return sampleStratified(sample, settings.samples, pixelIndex, settings.seed);
        case AntialiasMode::Adaptive: return sampleAdaptive(sample, settings.samples, pixelIndex, settings.seed);
    }
    return sampleCenter(sample);
}

}  // namespace ray
