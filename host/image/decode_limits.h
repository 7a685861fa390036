// The checks every image decoder makes before it allocates: a corrupt or hostile header can
// claim any size, so the claim is refused before memory is spent on it.
//
// Every image ray reads is a texture or a bump map, and a texture has a budget: the
// renderers sample it at most once a pixel of an image of at most 16384², so pixels beyond
// an 8K environment map buy nothing, while a few-kilobyte file claiming 13,000 × 13,000
// pixels would otherwise cost gigabytes before its data ran out.
#pragma once

#include <cstdint>
#include <filesystem>

namespace ray {

// At most 2^25 pixels a texture: 8192 × 4096, an 8K equirectangular environment; 16 times
// the course's largest (earth.png, 2000 × 1000).
constexpr uint64_t kMaxTexturePixels = uint64_t(1) << 25;
// The budget as messages say it.
inline constexpr const char* kTextureBudgetText = "2^25 (8192 × 4096)";

// The most one decode may hold at once, at the budget: the float image (12 bytes a pixel)
// and the decoder's own rows (at most 6 bytes a pixel: 16-bit RGB; OpenImageIO converts
// straight into the float image). The fuzzers' malloc limit is this (fuzz/fuzz_support.h),
// so that what they call too much is what ray would allocate.
constexpr uint64_t kMaxImageDecodeBytes = kMaxTexturePixels * (3 * sizeof(float) + 6);

// Throws ImageError naming the file when the image has no pixels, more than
// kMaxTexturePixels, or needs more host memory (bytesPerPixel of decoding buffers and the
// float image together) than the machine has (core/memory_limits.h).
void checkDecodedImageSize(const std::filesystem::path& file, uint64_t width, uint64_t height,
                           uint64_t bytesPerPixel);

}  // namespace ray
