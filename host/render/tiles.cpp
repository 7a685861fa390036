#include "render/tiles.h"

#include <algorithm>

namespace ray {

TileGrid::TileGrid(int width, int height, int side)
    : width_(width), height_(height), side_(std::max(1, side)),
      columns_((width + side_ - 1) / side_), rows_((height + side_ - 1) / side_) {}

TileRect TileGrid::tile(int index) const {
    const int tx = index % columns_, ty = index / columns_;
    return {tx * side_, ty * side_, std::min(side_, width_ - tx * side_), std::min(side_, height_ - ty * side_)};
}

int TileGrid::indexOf(const TileRect& rect) const {
    if (rect.x < 0 || rect.y < 0 || rect.x % side_ || rect.y % side_) return -1;
    const int tx = rect.x / side_, ty = rect.y / side_;
    if (tx >= columns_ || ty >= rows_) return -1;
    const int index = ty * columns_ + tx;
    const TileRect expected = tile(index);
    return expected.width == rect.width && expected.height == rect.height ? index : -1;
}

void pasteTile(Image& image, const TileRect& rect, const float* rgb) {
    const size_t rowFloats = size_t(rect.width) * 3;
    for (int row = 0; row < rect.height; ++row)
        std::copy_n(rgb + size_t(row) * rowFloats, rowFloats,
                    image.rgb.begin() + ptrdiff_t((size_t(rect.y + row) * size_t(image.width) + size_t(rect.x)) * 3));
}

void pasteTile(ByteImage& image, const TileRect& rect, const float* rgb) {
    const size_t rowValues = size_t(rect.width) * 3;
    for (int row = 0; row < rect.height; ++row) {
        const float* from = rgb + size_t(row) * rowValues;
        uint8_t* to = &image.rgb[(size_t(rect.y + row) * size_t(image.width) + size_t(rect.x)) * 3];
        for (size_t i = 0; i < rowValues; ++i) to[i] = uint8_t(quantize8(from[i]));
    }
}

}  // namespace ray
