#include "image/decode_limits.h"

#include <string>

#include "core/memory_limits.h"
#include "image/image.h"

namespace ray {

void checkDecodedImageSize(const std::filesystem::path& file, uint64_t width, uint64_t height,
                           uint64_t bytesPerPixel) {
    const std::string size = std::to_string(width) + " × " + std::to_string(height);
    if (width == 0 || height == 0) throw ImageError(file.string() + ": image has no pixels");
    // Each side is below 2^32 (the formats' own fields), so the product cannot overflow.
    if (width * height > kMaxTexturePixels)
        throw ImageError(file.string() + ": the image claims " + size +
                         " pixels, more than a texture's budget of " + kTextureBudgetText +
                         "; scale it down to at most 8192 × 4096");
    if (auto shortfall = hostMemoryShortfall(width * height * bytesPerPixel))
        throw ImageError(file.string() + ": a " + size + " image " + *shortfall);
}

}  // namespace ray
