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

}  // namespace

extern "C" {

__attribute__((visibility("default"))) int ray_oiio_open(const char* path, void** handle, RayOiioImageInfo* info,
                                                         char* error, size_t errorSize) {
    auto input = OIIO::ImageInput::open(path);
    if (!input) return fail(error, errorSize, "cannot read image: " + OIIO::geterror());
    const OIIO::ImageSpec& spec = input->spec();
    *info = RayOiioImageInfo{spec.width, spec.height, spec.nchannels};
    *handle = input.release();
    return 1;
}

__attribute__((visibility("default"))) int ray_oiio_read_rgb(void* handle, float* rgb, char* error,
                                                             size_t errorSize) {
    auto* input = static_cast<OIIO::ImageInput*>(handle);
    const OIIO::ImageSpec& spec = input->spec();
    const int channels = spec.nchannels;
    std::vector<float> pixels(size_t(spec.width) * size_t(spec.height) * size_t(channels));
    // Integer formats convert to [0, 1] as v / max, i.e. v/255 for 8-bit files.
    if (!input->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data()))
        return fail(error, errorSize, "cannot decode image: " + input->geterror());
    for (size_t p = 0, n = size_t(spec.width) * size_t(spec.height); p < n; ++p) {
        const float* src = &pixels[p * size_t(channels)];
        for (int c = 0; c < 3; ++c) rgb[p * 3 + size_t(c)] = channels >= 3 ? src[c] : src[0];
    }
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
