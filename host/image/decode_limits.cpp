#include "image/decode_limits.h"

#include <string>

#include "core/memory_limits.h"
#include "image/image.h"

namespace ray {

void checkDecodedImageSize(const std::filesystem::path& file, uint64_t width, uint64_t height,
                           uint64_t bytesPerPixel) {
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    if (width == 0 || height == 0) throw ImageError(file.string() + ": image has no pixels");
    if (width * height > kMaxImagePixels)
        throw ImageError(file.string() + ": image is " + size + ", larger than the 2^28-pixel limit");
    if (auto shortfall = hostMemoryShortfall(width * height * bytesPerPixel))
        throw ImageError(file.string() + ": a " + size + " image " + *shortfall);
}

}  // namespace ray
