// The checks every image decoder makes before it allocates: a corrupt or hostile header can
// claim any size, so the claim is refused before memory is spent on it.
#pragma once

#include <cstdint>
#include <filesystem>

namespace ray {

// At most 2^28 pixels an image (a 16384² texture is 2^28).
constexpr uint64_t kMaxImagePixels = uint64_t(1) << 28;

// Throws ImageError naming the file when the image has no pixels, more than
// kMaxImagePixels, or needs more host memory (bytesPerPixel of decoding buffers and the
// float image together) than the machine has (core/memory_limits.h).
void checkDecodedImageSize(const std::filesystem::path& file, uint64_t width, uint64_t height,
                           uint64_t bytesPerPixel);

}  // namespace ray
