// Reading and writing images: PNG and JPEG through libpng and libjpeg (png_codec.h says
// why), every other format through OpenImageIO, loaded only when needed (oiio_module.h).
// Every write goes through core/atomic_file.h: checked writes, fsync, rename.
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <system_error>

#include "image/image.h"
#include "core/atomic_file.h"
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

// Only regular files are read: opening a FIFO blocks until someone writes to it, and a
// device such as /dev/zero never ends.
static void checkRegularFile(const fs::path& file) {
    std::error_code ec;
    const fs::file_status status = fs::status(file, ec);
    if (ec) throw ImageError(file.string() + ": cannot read image: " + ec.message());
    if (!fs::is_regular_file(status))
        throw ImageError(file.string() + ": cannot read image: not a regular file (" +
                         (fs::is_fifo(status) ? "a FIFO" : fs::is_directory(status) ? "a folder" : "a device or socket") +
                         "); give an image file");
}

Image readImage(const fs::path& file) {
    checkRegularFile(file);
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

// Any format but PNG, through OpenImageIO's module: `samples` are 3 floats a pixel for a
// float format, else 3 bytes. The module writes the temporary file itself, which is then
// decoded again before the rename, so a write the encoder did not notice failing (a full
// disk once left a truncated image and "wrote out.png") cannot pass.
void writeWithOiio(const fs::path& file, int width, int height, const void* samples) {
    if (!oiioCanWrite(file))
        throw ImageError(file.string() + ": cannot write the output format '" + file.extension().string() + "'; " +
                         kOutputFormatAdvice);
    writeFileAtomicallyVia(file, [&](const fs::path& tmp) {
        writeImageWithOiio(tmp, file, width, height, isFloatFormat(file), samples);
        try {
            const Image check = readImageWithOiio(tmp);
            if (check.width != width || check.height != height) throw ImageError("wrong size");
        } catch (const ImageError& e) {
            throw ImageError(file.string() + ": cannot write image: the written file does not decode (" + e.what() +
                             "); is the disk full?");
        }
    });
}

void refuseEmpty(bool empty, const fs::path& file) {
    if (empty) throw ImageError(file.string() + ": refusing to write an empty image");
}

}  // namespace

ByteImage quantize8(const Image& image) {
    ByteImage bytes;
    bytes.width = image.width;
    bytes.height = image.height;
    bytes.rgb = quantize8(image.rgb.data(), image.rgb.size());
    return bytes;
}

void writeImage(const Image& image, const fs::path& file) {
    refuseEmpty(image.empty(), file);
    if (isFloatFormat(file))
        writeWithOiio(file, image.width, image.height, image.rgb.data());
    else
        writeImage(quantize8(image), file);
}

void writeImage(const ByteImage& image, const fs::path& file) {
    refuseEmpty(image.empty(), file);
    if (isFloatFormat(file))
        throw ImageError(file.string() + ": an 8-bit image cannot be written as floats; " + kOutputFormatAdvice);
    if (lowerExtension(file) == ".png") {
        // Encoded in memory by libpng, so every byte reaches the disk through checked writes.
        const std::vector<uint8_t> png = encodePng(image);
        writeFileAtomically(file, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
    } else {
        writeWithOiio(file, image.width, image.height, image.rgb.data());
    }
}

}  // namespace ray
