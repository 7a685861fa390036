// Images in memory, and reading and writing them: PNG and JPEG with libpng and libjpeg,
// other formats with OpenImageIO (loaded only when one is met: image/oiio_module.h).
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/math.h"

namespace ray {

// A linear RGB float image, row 0 at the top. Textures are stored this way too, with
// 8-bit values v mapped to v/255 exactly as the course does (no gamma decoding).
struct Image {
    int width = 0, height = 0;
    std::vector<float> rgb;  // width * height * 3

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgb(size_t(w) * size_t(h) * 3, 0.0f) {}

    bool empty() const { return width == 0 || height == 0; }
    Vec3 at(int x, int y) const {
        const float* p = &rgb[(size_t(y) * size_t(width) + size_t(x)) * 3];
        return {p[0], p[1], p[2]};
    }
    void set(int x, int y, const Vec3& c) {
        float* p = &rgb[(size_t(y) * size_t(width) + size_t(x)) * 3];
        p[0] = float(c.x);
        p[1] = float(c.y);
        p[2] = float(c.z);
    }
};

// An image as an 8-bit file holds it: quantize8 of each channel (below), row 0 at the top.
// What a render keeps when its output is an 8-bit file: a quarter of a float image's
// memory (a 4K frame: 25 MB instead of 100).
struct ByteImage {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;  // width * height * 3

    ByteImage() = default;
    ByteImage(int w, int h) : width(w), height(h), rgb(size_t(w) * size_t(h) * 3, 0) {}

    bool empty() const { return width == 0 || height == 0; }
};

// Thrown for an image that cannot be read or written; the message names the file.
struct ImageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Reads PNG and JPEG directly and any other format OpenImageIO understands (ppm, tif, exr …),
// chosen by the file's content. Grey images are expanded to RGB and alpha is dropped;
// integer samples become v / max. Throws ImageError.
Image readImage(const std::filesystem::path& file);

// True for outputs that keep floats unclamped (exr, hdr, pfm); others are 8-bit.
bool isFloatFormat(const std::filesystem::path& file);

// Whether this OpenImageIO build has a writer for the file's extension (Debian 12's reads
// pfm but cannot write it, for one). Asked before rendering, so that no render is lost.
bool canWriteImageFormat(const std::filesystem::path& file);

// The outputs to suggest when a format cannot be written.
extern const char* const kOutputFormatAdvice;

// Writes the image in the format its extension names. 8-bit formats get colors clamped to
// [0, 1] and truncated, floor(255·c), without gamma (SPEC §4); float formats keep the
// values as they are. Written atomically (core/atomic_file.h): an existing file is never
// left half-written. Throws ImageError (cannot encode) or FileWriteError (the disk: full,
// unwritable folder), whose message names the path and the system's reason.
void writeImage(const Image& image, const std::filesystem::path& file);

// Writes an 8-bit image to an 8-bit format (throws ImageError for a float one: its values
// are already quantized). The same bytes as writeImage of the float image it came from.
void writeImage(const ByteImage& image, const std::filesystem::path& file);

// The 8-bit value SPEC §4 writes for a color channel: floor(255·clamp(c, 0, 1)).
inline int quantize8(double c) {
    if (!(c > 0)) return 0;  // also maps NaN to 0
    if (c >= 1) return 255;
    return int(c * 255.0);
}

// quantize8 of `count` floats: the 8-bit values an 8-bit file of them holds.
inline std::vector<uint8_t> quantize8(const float* values, size_t count) {
    std::vector<uint8_t> bytes(count);
    for (size_t i = 0; i < count; ++i) bytes[i] = uint8_t(quantize8(values[i]));
    return bytes;
}

// The 8-bit image an 8-bit file of `image` holds.
ByteImage quantize8(const Image& image);

}  // namespace ray
