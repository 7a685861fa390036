// libray_oiio.so: the formats that are neither PNG nor JPEG (tif, exr, hdr, ppm, bmp …),
// through OpenImageIO, behind the C interface of oiio_plugin_abi.h. Built as a module of its
// own so that only a run that meets such a format pays for loading OpenImageIO.
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "image/oiio_plugin_abi.h"

namespace {

int fail(char* error, size_t errorSize, const std::string& message) {
    if (errorSize > 0) std::snprintf(error, errorSize, "%s", message.c_str());
    return 0;
}

// With a format, the reader is made for it and opens the file itself: ImageInput::open would
// fall back on every other reader when that one refuses the file. `why` receives the error.
std::unique_ptr<OIIO::ImageInput> openInput(const char* path, const char* format, std::string& why) {
    std::unique_ptr<OIIO::ImageInput> input =
        format && *format ? OIIO::ImageInput::create(format) : OIIO::ImageInput::open(path);
    OIIO::ImageSpec spec;
    if (input && format && *format && !input->open(path, spec)) {
        why = input->geterror();
        return nullptr;
    }
    if (!input) why = OIIO::geterror();
    return input;
}

}  // namespace

extern "C" {

__attribute__((visibility("default"))) int ray_oiio_open(const char* path, const char* format, void** handle,
                                                         RayOiioImageInfo* info, char* error, size_t errorSize) {
    std::string why;
    auto input = openInput(path, format, why);
    if (!input) return fail(error, errorSize, "cannot read image: " + why);
    const OIIO::ImageSpec& spec = input->spec();
    *info = RayOiioImageInfo{spec.width, spec.height, spec.nchannels};
    *handle = input.release();
    return 1;
}

__attribute__((visibility("default"))) int ray_oiio_read_rgb(void* handle, float* rgb, char* error,
                                                             size_t errorSize) {
    auto* input = static_cast<OIIO::ImageInput*>(handle);
    const OIIO::ImageSpec& spec = input->spec();
    // Straight into the RGB floats, three apart, so that no decoded copy of the whole image
    // exists beside them (OpenImageIO converts a bounded number of scanlines at a time).
    // Integer formats convert to [0, 1] as v / max, i.e. v/255 for 8-bit files. Grey (and
    // grey with alpha) is read into red and copied to green and blue; alpha is dropped.
    const int channels = spec.nchannels >= 3 ? 3 : 1;
    constexpr OIIO::stride_t kPixelStride = 3 * sizeof(float);
    if (!input->read_scanlines(0, 0, spec.y, spec.y + spec.height, spec.z, 0, channels, OIIO::TypeDesc::FLOAT, rgb,
                               kPixelStride))
        return fail(error, errorSize, "cannot decode image: " + input->geterror());
    if (channels == 1)
        for (size_t p = 0, n = size_t(spec.width) * size_t(spec.height); p < n; ++p)
            rgb[p * 3 + 1] = rgb[p * 3 + 2] = rgb[p * 3];
    return 1;
}

__attribute__((visibility("default"))) void ray_oiio_close(void* handle) {
    std::unique_ptr<OIIO::ImageInput> input(static_cast<OIIO::ImageInput*>(handle));
    if (input) input->close();
}

__attribute__((visibility("default"))) int ray_oiio_can_write(const char* path) {
    return OIIO::ImageOutput::create(path) != nullptr;
}

__attribute__((visibility("default"))) int ray_oiio_write(const char* path, int width, int height, int asFloat,
                                                          const void* samples, char* error, size_t errorSize) {
    auto output = OIIO::ImageOutput::create(path);
    if (!output) return fail(error, errorSize, "no writer for this format");
    const OIIO::TypeDesc type = asFloat ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
    OIIO::ImageSpec spec(width, height, 3, type);
    if (!output->open(path, spec) || !output->write_image(type, samples) || !output->close())
        return fail(error, errorSize, "cannot write image: " + output->geterror());
    return 1;
}

}  // extern "C"
