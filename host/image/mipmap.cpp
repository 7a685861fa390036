#include "image/mipmap.h"

#include <algorithm>
#include <cmath>

namespace ray {

namespace {

// The 8-bit value the kernel's texel buffer holds for a channel (as packTextures rounds).
double eightBit(double c) { return double(std::lround(std::clamp(c, 0.0, 1.0) * 255.0)); }

Image halve(const Image& source) {
    Image level(std::max(1, source.width / 2), std::max(1, source.height / 2));
    for (int y = 0; y < level.height; ++y) {
        int y0 = std::min(2 * y, source.height - 1), y1 = std::min(2 * y + 1, source.height - 1);
        for (int x = 0; x < level.width; ++x) {
            int x0 = std::min(2 * x, source.width - 1), x1 = std::min(2 * x + 1, source.width - 1);
            Vec3 sum;
            for (Vec3 c : {source.at(x0, y0), source.at(x1, y0), source.at(x0, y1), source.at(x1, y1)})
                sum += Vec3{eightBit(c.x), eightBit(c.y), eightBit(c.z)};
            // Round the mean of the four 8-bit values back to 8 bits.
            level.set(x, y, Vec3{std::round(sum.x / 4), std::round(sum.y / 4), std::round(sum.z / 4)} / 255.0);
        }
    }
    return level;
}

}  // namespace

std::vector<Image> buildMipLevels(const Image& base) {
    std::vector<Image> levels;
    const Image* previous = &base;
    while (previous->width > 1 || previous->height > 1) {
        levels.push_back(halve(*previous));
        previous = &levels.back();
    }
    return levels;
}

MipPyramid buildMipPyramid(const Image& base) {
    MipPyramid pyramid;
    pyramid.levels.push_back(base);
    for (Image& level : buildMipLevels(base)) pyramid.levels.push_back(std::move(level));
    return pyramid;
}

}  // namespace ray
