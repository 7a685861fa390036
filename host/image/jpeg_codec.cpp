// JPEG reading with libjpeg. Its errors longjmp back to readJpeg's setjmp (png_codec.cpp
// explains the discipline: C++ state lives behind a pointer set before setjmp).
#include "image/jpeg_codec.h"

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

// jpeglib.h needs size_t and FILE declared first.
#include <jpeglib.h>

#include "image/decode_limits.h"

namespace ray {
namespace fs = std::filesystem;

namespace {

struct JpegErrorManager {
    jpeg_error_mgr base;  // first, so that libjpeg's pointer to it is a pointer to this
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX] = "";
};

[[noreturn]] void onJpegError(j_common_ptr cinfo) {
    auto* manager = reinterpret_cast<JpegErrorManager*>(cinfo->err);
    (*cinfo->err->format_message)(cinfo, manager->message);
    std::longjmp(manager->jump, 1);
}

void ignoreJpegMessage(j_common_ptr, int) {}  // warnings (e.g. extraneous bytes) are not errors

struct FileCloser {
    void operator()(FILE* f) const { std::fclose(f); }
};

struct JpegDecode {
    std::vector<uint8_t> pixels;
    std::string failure;
};

}  // namespace

bool hasJpegSignature(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    unsigned char marker[3] = {};
    return in.read(reinterpret_cast<char*>(marker), 3) && marker[0] == 0xFF && marker[1] == 0xD8 && marker[2] == 0xFF;
}

Image readJpeg(const fs::path& file) {
    std::unique_ptr<FILE, FileCloser> in(std::fopen(file.c_str(), "rb"));
    if (!in) throw ImageError(file.string() + ": cannot read image: " + std::strerror(errno));
    jpeg_decompress_struct cinfo;
    JpegErrorManager errors;
    cinfo.err = jpeg_std_error(&errors.base);
    errors.base.error_exit = onJpegError;
    errors.base.emit_message = ignoreJpegMessage;
    const auto state = std::make_unique<JpegDecode>();
    if (setjmp(errors.jump)) {
        jpeg_destroy_decompress(&cinfo);
        throw ImageError(file.string() + ": cannot decode image: " + errors.message);
    }
    jpeg_create_decompress(&cinfo);
    jpeg_stdio_src(&cinfo, in.get());
    jpeg_read_header(&cinfo, TRUE);
    cinfo.out_color_space = JCS_RGB;  // libjpeg converts grey and YCbCr (CMYK fails: reported)
    const uint64_t width = cinfo.image_width, height = cinfo.image_height;
    try {
        checkDecodedImageSize(file, width, height, 3 + 3 * sizeof(float));  // the decoded bytes, the floats
    } catch (const ImageError& e) {
        state->failure = e.what();
    }
    if (state->failure.empty()) {
        jpeg_start_decompress(&cinfo);
        if (cinfo.output_components != 3) {
            state->failure = file.string() + ": cannot decode image: not convertible to RGB";
            jpeg_destroy_decompress(&cinfo);
            throw ImageError(state->failure);
        }
        const size_t rowBytes = size_t(cinfo.output_width) * 3;
        state->pixels.resize(rowBytes * cinfo.output_height);
        while (cinfo.output_scanline < cinfo.output_height) {
            JSAMPROW row = state->pixels.data() + size_t(cinfo.output_scanline) * rowBytes;
            jpeg_read_scanlines(&cinfo, &row, 1);
        }
        jpeg_finish_decompress(&cinfo);
    }
    jpeg_destroy_decompress(&cinfo);
    if (!state->failure.empty()) throw ImageError(state->failure);
    Image image{int(width), int(height)};
    // v · (1/255) in float, exactly as OpenImageIO converts bytes (png_codec.cpp).
    for (size_t i = 0; i < state->pixels.size(); ++i) image.rgb[i] = float(state->pixels[i]) * (1.0f / 255.0f);
    return image;
}

}  // namespace ray
