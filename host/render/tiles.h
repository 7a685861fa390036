// A frame cut into tiles: the unit of work the OpenCL engine's devices and the ranks of a
// distributed render take one at a time.
#pragma once

#include <cstddef>

#include "image/image.h"

namespace ray {

// A rectangle of the image, in pixels: columns x..x+width-1, rows y..y+height-1.
struct TileRect {
    int x = 0, y = 0, width = 0, height = 0;

    size_t pixels() const { return size_t(width) * size_t(height); }
};

// The image as a grid of square tiles of one side, numbered row by row; the last column
// and row are cut to the image.
class TileGrid {
public:
    TileGrid(int width, int height, int side);
    int count() const { return columns_ * rows_; }
    int side() const { return side_; }
    TileRect tile(int index) const;
    // The index of a tile of this grid (its rectangle as tile() gives it); -1 for a
    // rectangle that is not one.
    int indexOf(const TileRect& rect) const;

private:
    int width_, height_, side_, columns_, rows_;
};

// Copies a tile's linear RGB (3 floats a pixel, row by row) into its place in the image.
void pasteTile(Image& image, const TileRect& rect, const float* rgb);
// The same into an 8-bit image, each channel quantize8 (image/image.h).
void pasteTile(ByteImage& image, const TileRect& rect, const float* rgb);

}  // namespace ray
