// JPEG textures through libjpeg(-turbo) directly, for the reason png_codec.h gives: the
// course's other texture format, decoded without loading OpenImageIO.
#pragma once

#include <filesystem>

#include "image/image.h"

namespace ray {

// True when the file starts with a JPEG start-of-image marker (FF D8 FF).
bool hasJpegSignature(const std::filesystem::path& file);

// Decodes a JPEG with libjpeg's defaults (the decoder OpenImageIO uses, with the same
// settings), as RGB with v / 255 floats; grey and CMYK are converted by libjpeg to RGB.
// Throws ImageError naming the file.
Image readJpeg(const std::filesystem::path& file);

}  // namespace ray
