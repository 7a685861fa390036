#include "image/oiio_module.h"

#include <mutex>
#include <string>

#include "core/module_loader.h"
#include "image/decode_limits.h"
#include "image/oiio_plugin_abi.h"

namespace ray {
namespace fs = std::filesystem;

namespace {

constexpr ModuleSpec kOiioModule{"libray_oiio.so", "RAY_OIIO_MODULE", "ray's OpenImageIO module"};

struct OiioModule {
    RayOiioOpen open = nullptr;
    RayOiioReadRgb readRgb = nullptr;
    RayOiioClose close = nullptr;
    RayOiioCanWrite canWrite = nullptr;
    RayOiioWrite write = nullptr;
    std::string failure;  // why it could not be loaded; empty once loaded
};

OiioModule loadOiioModule() {
    OiioModule module;
    LoadedModule loaded = loadModule(kOiioModule);
    const bool complete = resolveEntryPoint(loaded, RAY_OIIO_OPEN, module.open) &&
                          resolveEntryPoint(loaded, RAY_OIIO_READ_RGB, module.readRgb) &&
                          resolveEntryPoint(loaded, RAY_OIIO_CLOSE, module.close) &&
                          resolveEntryPoint(loaded, RAY_OIIO_CAN_WRITE, module.canWrite) &&
                          resolveEntryPoint(loaded, RAY_OIIO_WRITE, module.write);
    if (!complete) module.failure = loaded.failure;  // what was missing, where ray looked
    return module;
}

// Loaded once per process, on first use; later calls wait for the first.
const OiioModule& oiioModule() {
    static std::once_flag once;
    static OiioModule module;
    std::call_once(once, [] { module = loadOiioModule(); });
    return module;
}

const OiioModule& requireModule(const fs::path& file) {
    const OiioModule& module = oiioModule();
    if (!module.failure.empty()) throw ImageError(file.string() + ": " + module.failure);
    return module;
}

}  // namespace

std::string preloadOiioModule() {
    const OiioModule& module = oiioModule();
    if (module.failure.empty()) {
        // A file of no known extension makes OpenImageIO try every format, which readies each
        // of its readers (about 1 s under full unwinding, once per process).
        char error[256] = "";
        void* handle = nullptr;
        RayOiioImageInfo info{};
        if (module.open("/dev/null", nullptr, &handle, &info, error, sizeof error)) module.close(handle);
    }
    return module.failure;
}

Image readImageWithOiio(const fs::path& file, std::string_view format) {
    const OiioModule& module = requireModule(file);
    char error[1024] = "";
    void* handle = nullptr;
    RayOiioImageInfo info{};
    const std::string formatName(format);
    if (!module.open(file.c_str(), formatName.c_str(), &handle, &info, error, sizeof error)) throw ImageError(file.string() + ": " + error);
    struct Closer {
        const OiioModule& module;
        void* handle;
        ~Closer() { module.close(handle); }
    } closer{module, handle};
    if (info.width < 0 || info.height < 0 || info.channels <= 0)  // zero sizes: checkDecodedImageSize
        throw ImageError(file.string() + ": image has no pixels");
    // The module decodes straight into the RGB floats.
    checkDecodedImageSize(file, uint64_t(info.width), uint64_t(info.height), 3 * sizeof(float));
    Image image(info.width, info.height);
    if (!module.readRgb(handle, image.rgb.data(), error, sizeof error)) throw ImageError(file.string() + ": " + error);
    return image;
}

bool oiioCanWrite(const fs::path& file) {
    const OiioModule& module = oiioModule();
    return module.failure.empty() && module.canWrite(file.c_str());
}

void writeImageWithOiio(const fs::path& file, const fs::path& target, int width, int height, bool asFloat,
                        const void* samples) {
    const OiioModule& module = requireModule(target);
    char error[1024] = "";
    if (!module.write(file.c_str(), width, height, asFloat ? 1 : 0, samples, error, sizeof error))
        throw ImageError(target.string() + ": " + error);
}

}  // namespace ray
