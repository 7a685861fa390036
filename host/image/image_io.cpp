// Reading and writing images: PNG and JPEG through libpng and libjpeg (png_codec.h says
// why), every other format through OpenImageIO, loaded only when needed (oiio_module.h).
// Every write goes through core/atomic_file.h: checked writes, fsync, rename.
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <string_view>

#include "image/image.h"
#include "image/image_write.h"
#include "core/atomic_file.h"
#include "core/input_file.h"
#include "image/decode_limits.h"
#include "image/header_checks.h"
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

// A texture file holds at most its budget of pixels (image/decode_limits.h), 4 floats each
// at the most (an uncompressed RGBA float TIFF or EXR), and its metadata.
constexpr InputLimit kTextureFileLimit{"an image", kMaxTexturePixels * 16 + (uint64_t(64) << 20),
                                       "2^25 pixels of 4 floats, a texture's budget, and metadata"};

// A TGA header's fields in their ranges: a colour map type of 0 or 1, a known image type,
// a known pixel depth and both sides non-zero (text fails the first test).
bool looksLikeTga(const std::string& h) {
    if (h.size() < 18) return false;
    const auto byte = [&](size_t i) { return static_cast<unsigned char>(h[i]); };
    const bool colorMap = byte(1) <= 1;
    const bool imageType = std::string_view("\x01\x02\x03\x09\x0a\x0b").find(char(byte(2))) != std::string_view::npos;
    const bool depth = byte(16) == 8 || byte(16) == 15 || byte(16) == 16 || byte(16) == 24 || byte(16) == 32;
    const bool sides = (byte(12) | byte(13)) != 0 && (byte(14) | byte(15)) != 0;
    return colorMap && imageType && depth && sides;
}

bool startsWith(const std::string& header, std::string_view prefix) {
    return header.size() >= prefix.size() && header.compare(0, prefix.size(), prefix) == 0;
}

// The reader a file's first bytes call for, as OpenImageIO names it by extension ("tga"),
// or empty: PNG, JPEG, OpenEXR, Radiance HDR, TIFF, PNM and PFM, BMP, GIF and WebP, or a
// plausible TGA header (TGA has no signature; ray reads one by content whatever its name,
// as it does the others). The file is then decoded by that reader alone (oiio_module.h).
// Anything else is refused at once: OpenImageIO would try every reader it has on it (a
// 128 MiB file of text took 18 s), and its readers of formats nobody paints textures in
// are the least hardened (fuzz_image_reader crashed its Softimage PIC reader on a NULL
// FILE*, reached through a TGA-named file when the TGA reader refused it): those (PIC, IFF,
// FITS, DPX, Cineon, ICO, DDS, PSD, SGI, JPEG 2000, HEIF) are never reached.
std::string_view imageFormatOf(const std::string& h, const fs::path& file) {
    using namespace std::string_view_literals;
    static const std::pair<std::string_view, std::string_view> kSignatures[] = {
        {"\x89PNG"sv, "png"}, {"\xff\xd8\xff"sv, "jpg"}, {"\x76\x2f\x31\x01"sv, "exr"}, {"#?"sv, "hdr"},
        {"II*\0"sv, "tif"},   {"MM\0*"sv, "tif"},        {"II+\0"sv, "tif"},             {"MM\0+"sv, "tif"},
        {"BM"sv, "bmp"},      {"GIF8"sv, "gif"}};
    for (const auto& [signature, format] : kSignatures)
        if (startsWith(h, signature)) return format;
    if (h.size() >= 2 && h[0] == 'P' && std::string_view("1234567Ff").find(h[1]) != std::string_view::npos) return "pnm";
    if (startsWith(h, "RIFF") && h.size() >= 12 && h.compare(8, 4, "WEBP") == 0) return "webp";
    return looksLikeTga(h) || lowerExtension(file) == ".tga" ? "tga" : "";
}

std::string firstBytes(const fs::path& file, size_t count) {
    std::ifstream in(file, std::ios::binary);
    std::string header(count, '\0');
    in.read(header.data(), std::streamsize(count));
    header.resize(size_t(in.gcount()));
    return header;
}

// Only a regular file of a size a texture can need, holding an image format's signature, is
// decoded: opening a FIFO blocks until someone writes to it, a device such as /dev/zero
// never ends, and a large file of anything else kept OpenImageIO busy for seconds. Returns
// the format (imageFormatOf).
std::string_view checkImageFile(const fs::path& file) {
    try {
        checkInputFile(file, kTextureFileLimit);
    } catch (const InputFileError& e) {
        throw ImageError(e.what());
    }
    const std::string_view format = imageFormatOf(firstBytes(file, 18), file);
    if (format.empty())
        throw ImageError(file.string() + ": cannot read image: its first bytes are those of no image format ray reads; "
                         "give a PNG, JPEG, OpenEXR, HDR, TIFF, PPM, BMP, GIF, WebP or TGA file");
    return format;
}

}  // namespace

Image readImage(const fs::path& file) {
    const std::string_view format = checkImageFile(file);
    checkPngChunkLengths(file);
    checkGifScreenSize(file);
    // By content, not by extension: a texture named .png may hold a JPEG.
    if (format == "png") return readPng(file);
    if (format == "jpg") return readJpeg(file);
    return readImageWithOiio(file, format);
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
void writeWithOiio(const fs::path& file, int width, int height, const void* samples, const WriteOptions& options) {
    if (!oiioCanWrite(file))
        throw ImageError(file.string() + ": cannot write the output format '" + file.extension().string() + "'; " +
                         kOutputFormatAdvice);
    writeFileAtomicallyVia(file, [&](const fs::path& tmp) {
        writeImageWithOiio(tmp, file, width, height, isFloatFormat(file), samples);
        try {
            const Image check = readImageWithOiio(tmp, lowerExtension(file).substr(1));
            if (check.width != width || check.height != height) throw ImageError("wrong size");
        } catch (const ImageError& e) {
            throw ImageError(file.string() + ": cannot write image: the written file does not decode (" + e.what() +
                             "); is the disk full?");
        }
    }, options);
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

void writeImage(const Image& image, const fs::path& file) { writeImage(image, file, WriteOptions{}); }

void writeImage(const ByteImage& image, const fs::path& file) { writeImage(image, file, WriteOptions{}); }

void writeImage(const Image& image, const fs::path& file, const WriteOptions& options) {
    refuseEmpty(image.empty(), file);
    if (isFloatFormat(file))
        writeWithOiio(file, image.width, image.height, image.rgb.data(), options);
    else
        writeImage(quantize8(image), file, options);
}

void writeImage(const ByteImage& image, const fs::path& file, const WriteOptions& options) {
    refuseEmpty(image.empty(), file);
    if (isFloatFormat(file))
        throw ImageError(file.string() + ": an 8-bit image cannot be written as floats; " + kOutputFormatAdvice);
    if (lowerExtension(file) == ".png") {
        // Encoded in memory by libpng, so every byte reaches the disk through checked writes.
        const std::vector<uint8_t> png = encodePng(image);
        writeFileAtomically(file, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()), options);
    } else {
        writeWithOiio(file, image.width, image.height, image.rgb.data(), options);
    }
}

}  // namespace ray
