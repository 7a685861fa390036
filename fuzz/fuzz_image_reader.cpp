// libFuzzer target: texture decoding. The bytes are written to a file that ray::readImage
// (OpenImageIO) opens as it opens a texture; the extension-less name makes OpenImageIO
// sniff the format from the contents, so one target reaches every decoder.
//
// Anything but a clean ImageError is a crash. Seeds: the course's images and our textures.
#include <cstdint>

#include "fuzz_support.h"
#include "image/decode_limits.h"
#include "image/image.h"
#include "image/oiio_module.h"

// OpenImageIO is loaded before the first input, so that libFuzzer's per-input timeout
// (-timeout=10 in scripts/fuzz.sh) times decoding, not the seconds of dlopen under full
// unwinding (it timed out so on a loaded CI machine). A missing module is not an error here:
// every input then meets it as a clean ImageError. No decode may allocate more than a
// texture's budget allows.
extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
    ray::fuzz::limitMallocTo(ray::kMaxImageDecodeBytes, argc, argv);
    ray::preloadOiioModule();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const auto file = ray::fuzz::scratchFolder() / "texture";
    ray::fuzz::writeBytes(file, data, size);
    try {
        ray::Image image = ray::readImage(file);
        if (image.width <= 0 || image.height <= 0 || image.rgb.size() != size_t(image.width) * size_t(image.height) * 3)
            __builtin_trap();  // readImage promises a whole image or an exception
    } catch (const ray::ImageError&) {
    }
    return 0;
}
