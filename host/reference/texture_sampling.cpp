#include "reference/texture_sampling.h"

#include <algorithm>
#include <cmath>

namespace ray {

namespace {

double fract(double x) { return x - std::floor(x); }

// x modulo n, into [0, n) also for negative x.
int wrap(int x, int n) {
    int r = x % n;
    return r < 0 ? r + n : r;
}

}  // namespace

Vec3 sampleNearest(const Image& texture, double u, double v, double repeatU, double repeatV) {
    double s = fract(u * repeatU), t = fract(v * repeatV);
    int column = std::clamp(int(std::floor(s * texture.width)), 0, texture.width - 1);
    int row = std::clamp(int(std::floor((1 - t) * texture.height)), 0, texture.height - 1);
    return texture.at(column, row);
}

// Bilinear interpolation at continuous texel coordinates (x, y) in which integers name
// texel corners: texel (i, j) is the sample at (i, j), neighbours wrap around.
Vec3 bilinearAt(const Image& texture, double x, double y) {
    double x0 = std::floor(x), y0 = std::floor(y);
    double fx = x - x0, fy = y - y0;
    int left = wrap(int(x0), texture.width), right = wrap(int(x0) + 1, texture.width);
    int top = wrap(int(y0), texture.height), bottom = wrap(int(y0) + 1, texture.height);
    Vec3 upper = (1 - fx) * texture.at(left, top) + fx * texture.at(right, top);
    Vec3 lower = (1 - fx) * texture.at(left, bottom) + fx * texture.at(right, bottom);
    return (1 - fy) * upper + fy * lower;
}

Vec3 sampleBilinear(const Image& texture, double u, double v, double repeatU, double repeatV) {
    double s = fract(u * repeatU), t = fract(v * repeatV);
    // Shifted by half a texel so that integers are texel centres.
    return bilinearAt(texture, s * texture.width - 0.5, (1 - t) * texture.height - 0.5);
}

Vec3 sampleCourseBilinear(const Image& texture, double u, double v, double repeatU, double repeatV) {
    double s = fract(u * repeatU), t = fract(v * repeatV);
    return bilinearAt(texture, s * texture.width, (1 - t) * texture.height);
}

Vec3 sampleTexture(const Image& texture, double u, double v, double repeatU, double repeatV, TextureFilter filter) {
    switch (filter) {
        case TextureFilter::Nearest: return sampleNearest(texture, u, v, repeatU, repeatV);
        case TextureFilter::Course: return sampleCourseBilinear(texture, u, v, repeatU, repeatV);
        case TextureFilter::Bilinear:
        case TextureFilter::Trilinear: return sampleBilinear(texture, u, v, repeatU, repeatV);
    }
    return sampleNearest(texture, u, v, repeatU, repeatV);
}

}  // namespace ray
