// Reading and writing images: PNG and JPEG through libpng and libjpeg (png_codec.h says
// why), every other format through OpenImageIO, loaded only when needed (oiio_module.h).
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <system_error>

#include "image/image.h"
#include "image/jpeg_codec.h"
#include "image/oiio_module.h"
#include "image/png_codec.h"

namespace ray {
namespace fs = std::filesystem;

namespace {

std::string lowerExtension(const fs::path& file) {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

// A file beside the target, with the same extension so OpenImageIO picks the same format.
fs::path temporarySibling(const fs::path& file) {
    std::string name = ".";
    name += file.stem().string();
    name += ".tmp" + std::to_string(getpid());
    name += file.extension().string();
    fs::path tmp = file;
    tmp.replace_filename(name);
    return tmp;
}

// libpng allocates (and clears) a chunk's whole declared length before reading it, so a
// 1.6 KB PNG whose text chunk claims 1.9 GB took 10 s and 2 GB (found by
// fuzz_image_reader; tests/data/fuzz/image_reader/png_chunk_claims_2gb.png). No chunk can be longer
// than the file, so such a file is refused before OpenImageIO opens it.
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

}  // namespace

Image readImage(const fs::path& file) {
    checkPngChunkLengths(file);
    // By content, not by extension: a texture named .png may hold a JPEG.
    if (hasPngSignature(file)) return readPng(file);
    if (hasJpegSignature(file)) return readJpeg(file);
    return readImageWithOiio(file);
}

bool isFloatFormat(const fs::path& file) {
    std::string ext = lowerExtension(file);
    return ext == ".exr" || ext == ".hdr" || ext == ".pfm";
}

const char* const kOutputFormatAdvice = "use .png, .jpg, .tif, .ppm (8-bit) or .exr, .hdr (float)";

bool canWriteImageFormat(const fs::path& file) {
    if (lowerExtension(file) == ".png") return true;
    return !file.extension().empty() && oiioCanWrite(file);
}

namespace {

// Writes the file's bytes to a temporary sibling and renames it over the target.
void writeBytesReplacing(const fs::path& file, const std::vector<uint8_t>& bytes) {
    fs::path tmp = temporarySibling(file);
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
        out.close();
        if (!out) {
            std::error_code ignored;
            fs::remove(tmp, ignored);
            throw ImageError(file.string() + ": cannot write image");
        }
    }
    std::error_code ec;
    fs::rename(tmp, file, ec);
    if (ec) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw ImageError(file.string() + ": cannot write image: " + ec.message());
    }
}

// Any format but PNG: OpenImageIO writes a temporary sibling, renamed over the target.
void writeWithOiio(const Image& image, const fs::path& file) {
    if (!oiioCanWrite(file))
        throw ImageError(file.string() + ": cannot write the output format '" + file.extension().string() + "'; " +
                         kOutputFormatAdvice);
    const bool floats = isFloatFormat(file);
    std::vector<uint8_t> bytes;
    const void* data = image.rgb.data();
    if (!floats) {
        bytes.resize(image.rgb.size());
        for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = uint8_t(quantize8(image.rgb[i]));
        data = bytes.data();
    }
    fs::path tmp = temporarySibling(file);
    try {
        writeImageWithOiio(tmp, file, image.width, image.height, floats, data);
    } catch (...) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw;
    }
    std::error_code ec;
    fs::rename(tmp, file, ec);
    if (ec) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw ImageError(file.string() + ": cannot write image: " + ec.message());
    }
}

}  // namespace

void writeImage(const Image& image, const fs::path& file) {
    if (image.empty()) throw ImageError(file.string() + ": refusing to write an empty image");
    if (lowerExtension(file) == ".png")
        writeBytesReplacing(file, encodePng(image));
    else
        writeWithOiio(image, file);
}

}  // namespace ray
