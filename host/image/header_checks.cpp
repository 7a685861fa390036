#include "image/header_checks.h"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <string>
#include <system_error>

#include "image/decode_limits.h"
#include "image/image.h"

namespace ray {
namespace fs = std::filesystem;

void checkPngChunkLengths(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    unsigned char signature[8] = {};
    static const unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (!in.read(reinterpret_cast<char*>(signature), 8) || !std::equal(signature, signature + 8, kPngSignature)) return;
    std::error_code ec;
    const uint64_t fileSize = fs::file_size(file, ec);
    if (ec) return;
    uint64_t offset = 8;
    unsigned char header[8];
    while (in.read(reinterpret_cast<char*>(header), 8)) {
        const uint64_t length = uint64_t(header[0]) << 24 | uint64_t(header[1]) << 16 | uint64_t(header[2]) << 8 | header[3];
        const std::string type(reinterpret_cast<const char*>(header + 4), 4);
        if (offset + 12 + length > fileSize)
            throw ImageError(file.string() + ": corrupt PNG: its " + type + " chunk claims " + std::to_string(length) +
                             " bytes, more than the file holds");
        if (type == "IEND") return;
        offset += 12 + length;
        in.seekg(std::streamoff(offset));
    }
}

void checkGifScreenSize(const fs::path& file) {
    // "GIF87a" or "GIF89a", then the logical screen's width and height, little-endian.
    std::ifstream in(file, std::ios::binary);
    unsigned char header[10] = {};
    if (!in.read(reinterpret_cast<char*>(header), 10) || std::string(reinterpret_cast<char*>(header), 4) != "GIF8")
        return;
    const uint64_t width = header[6] | uint64_t(header[7]) << 8;
    const uint64_t height = header[8] | uint64_t(header[9]) << 8;
    // OpenImageIO's canvas: 4 bytes a pixel, beside the float image ray reads it into.
    checkDecodedImageSize(file, width, height, 4 + 3 * sizeof(float));
}

}  // namespace ray
