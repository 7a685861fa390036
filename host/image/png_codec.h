// PNG through libpng directly: the common texture format and the default output.
//
// Why not OpenImageIO here: loading libOpenImageIO.so (Debian 12: 261 shared libraries,
// OpenCV, FFmpeg, GDAL, DCMTK …) costs about 0.32 s and 130 MB before main() could do
// anything, longer than a whole render of a course scene. libpng loads in a millisecond.
// OpenImageIO stays for every other format (oiio_module.h), loaded only when one is met.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "image/image.h"

namespace ray {

// True when the file starts with the PNG signature.
bool hasPngSignature(const std::filesystem::path& file);

// Decodes a PNG as OpenImageIO does: raw sample values without gamma decoding, v / 255
// (16-bit: v / 65535) as floats, palettes expanded, grey copied to RGB, alpha dropped.
// Throws ImageError naming the file.
Image readPng(const std::filesystem::path& file);

// 8-bit RGB PNG bytes of the image. Compressed for speed (zlib level 1, the Sub filter): a
// render's output should not take longer to compress than to render, and these files are
// read back by tools, not shipped.
std::vector<uint8_t> encodePng(const ByteImage& image);

}  // namespace ray
