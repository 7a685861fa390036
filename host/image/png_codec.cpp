// PNG reading and writing with libpng's progressive-free, low-level API.
//
// libpng reports errors by longjmp to the setjmp in the function that started the
// operation. Every C++ object those functions own is created before setjmp and stays in
// scope, so the jump skips no destructor (only libpng's C frames lie between); what they
// change after setjmp lives on the heap; the error text is copied into a plain buffer and
// thrown as ImageError after the jump.
#include "image/png_codec.h"

#include <png.h>
#include <zlib.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>

#include "image/decode_limits.h"

namespace ray {
namespace fs = std::filesystem;

namespace {

// Refused before decoding, as every image reader does (image_io.cpp).
constexpr uint32_t kMaxSide = 1u << 20;

struct PngErrorText {
    char message[256] = "unknown libpng error";
};

[[noreturn]] void onPngError(png_structp png, png_const_charp message) {
    auto* text = static_cast<PngErrorText*>(png_get_error_ptr(png));
    std::snprintf(text->message, sizeof text->message, "%s", message);
    png_longjmp(png, 1);
}

void onPngWarning(png_structp, png_const_charp) {}  // benign (e.g. an unknown sRGB profile)

struct FileCloser {
    void operator()(FILE* f) const { std::fclose(f); }
};

// Asks libpng for the conversions that give 8- or 16-bit RGB with the file's raw values:
// palettes and low-bit grey expanded, grey copied to RGB, alpha and tRNS dropped. No gamma
// transform is set, so gAMA/sRGB chunks do not change the values (the course reads the
// raw 8-bit values as v/255, SPEC §5).
void requestRawRgb(png_structp png, png_infop info) {
    const int colorType = png_get_color_type(png, info);
    const int bitDepth = png_get_bit_depth(png, info);
    if (colorType == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (colorType == PNG_COLOR_TYPE_GRAY && bitDepth < 8) png_set_expand_gray_1_2_4_to_8(png);
    if (colorType == PNG_COLOR_TYPE_GRAY || colorType == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(png);
    if (colorType & PNG_COLOR_MASK_ALPHA) png_set_strip_alpha(png);
    if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS(png, info, nullptr, 0, nullptr), png_set_strip_alpha(png);
    if (bitDepth == 16) png_set_swap(png);  // host-order uint16_t on little-endian machines
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
}

// Integer samples to floats exactly as OpenImageIO converts them: v · (1/max) in float
// (not v / max, which differs in the last bit for half the byte values).
Image toFloatImage(const std::vector<uint8_t>& rows, uint32_t width, uint32_t height, bool sixteenBit) {
    Image image{int(width), int(height)};
    const size_t n = size_t(width) * height * 3;
    if (sixteenBit) {
        const auto* samples = reinterpret_cast<const uint16_t*>(rows.data());
        for (size_t i = 0; i < n; ++i) image.rgb[i] = float(samples[i]) * (1.0f / 65535.0f);
    } else {
        for (size_t i = 0; i < n; ++i) image.rgb[i] = float(rows[i]) * (1.0f / 255.0f);
    }
    return image;
}

}  // namespace

bool hasPngSignature(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    unsigned char signature[8] = {};
    return in.read(reinterpret_cast<char*>(signature), 8) && png_sig_cmp(signature, 0, 8) == 0;
}

// What a decode builds, on the heap: longjmp leaves automatic variables that were changed
// after setjmp indeterminate, but not objects reached through an unchanged pointer.
struct PngDecode {
    std::vector<uint8_t> rows;
    std::vector<png_bytep> rowPointers;
    uint32_t width = 0, height = 0;
    bool sixteenBit = false;
    std::string failure;  // an error of ours, thrown once libpng's structures are freed
};

Image readPng(const fs::path& file) {
    std::unique_ptr<FILE, FileCloser> in(std::fopen(file.c_str(), "rb"));
    if (!in) throw ImageError(file.string() + ": cannot read image: " + std::strerror(errno));
    PngErrorText error;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &error, onPngError, onPngWarning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!info) {
        png_destroy_read_struct(&png, nullptr, nullptr);
        throw ImageError(file.string() + ": cannot read image: out of memory");
    }
    const auto state = std::make_unique<PngDecode>();
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, nullptr);
        throw ImageError(file.string() + ": cannot decode image: " + error.message);
    }
    png_set_user_limits(png, kMaxSide, kMaxSide);
    png_init_io(png, in.get());
    png_read_info(png, info);
    state->width = png_get_image_width(png, info);
    state->height = png_get_image_height(png, info);
    try {
        // The decoded rows (up to 6 bytes a pixel) and the float image.
        checkDecodedImageSize(file, state->width, state->height, 6 + 3 * sizeof(float));
    } catch (const ImageError& e) {
        state->failure = e.what();
    }
    if (state->failure.empty()) {
        requestRawRgb(png, info);
        state->sixteenBit = png_get_bit_depth(png, info) == 16;
        const size_t rowBytes = png_get_rowbytes(png, info);
        if (rowBytes != size_t(state->width) * 3 * (state->sixteenBit ? 2 : 1)) png_error(png, "unexpected row layout");
        state->rows.resize(rowBytes * state->height);
        state->rowPointers.resize(state->height);
        for (uint32_t y = 0; y < state->height; ++y) state->rowPointers[y] = state->rows.data() + size_t(y) * rowBytes;
        png_read_image(png, state->rowPointers.data());
        png_read_end(png, nullptr);
    }
    png_destroy_read_struct(&png, &info, nullptr);
    if (!state->failure.empty()) throw ImageError(state->failure);
    return toFloatImage(state->rows, state->width, state->height, state->sixteenBit);
}

namespace {

void appendToVector(png_structp png, png_bytep data, png_size_t length) {
    auto* out = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(png));
    out->insert(out->end(), data, data + length);
}

void noFlush(png_structp) {}

}  // namespace

std::vector<uint8_t> encodePng(const ByteImage& image) {
    if (image.empty()) throw ImageError("refusing to encode an empty image");
    const std::vector<uint8_t>& pixels = image.rgb;
    const auto encoded = std::make_unique<std::vector<uint8_t>>();  // reached after a longjmp too
    encoded->reserve(pixels.size() / 4);
    PngErrorText error;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, onPngError, onPngWarning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!info) {
        png_destroy_write_struct(&png, nullptr);
        throw ImageError("cannot encode PNG: out of memory");
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        throw ImageError(std::string("cannot encode PNG: ") + error.message);
    }
    png_set_write_fn(png, encoded.get(), appendToVector, noFlush);
    png_set_IHDR(png, info, png_uint_32(image.width), png_uint_32(image.height), 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, Z_BEST_SPEED);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
    png_write_info(png, info);
    const size_t rowBytes = size_t(image.width) * 3;
    for (int y = 0; y < image.height; ++y) png_write_row(png, pixels.data() + size_t(y) * rowBytes);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return std::move(*encoded);
}

}  // namespace ray
