#include "image/oiio_module.h"

#include <dlfcn.h>

#include <cstdlib>
#include <mutex>
#include <string>
#include <vector>

#include "image/decode_limits.h"
#include "image/oiio_plugin_abi.h"

namespace ray {
namespace fs = std::filesystem;

namespace {

constexpr const char* kModuleName = "libray_oiio.so";

struct OiioModule {
    RayOiioOpen open = nullptr;
    RayOiioReadRgb readRgb = nullptr;
    RayOiioClose close = nullptr;
    RayOiioCanWrite canWrite = nullptr;
    RayOiioWrite write = nullptr;
    std::string failure;  // why it could not be loaded; empty once loaded
};

// The folder of the binary or shared library this function was linked into.
fs::path folderOfThisCode() {
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&folderOfThisCode), &info) == 0 || !info.dli_fname) return {};
    std::error_code ec;
    fs::path object = fs::canonical(info.dli_fname, ec);
    return ec ? fs::path() : object.parent_path();
}

std::vector<fs::path> moduleCandidates() {
    std::vector<fs::path> candidates;
    if (const char* explicitPath = std::getenv("RAY_OIIO_MODULE"); explicitPath && *explicitPath) {
        candidates.emplace_back(explicitPath);
        return candidates;  // a path set on purpose is the only one tried
    }
    if (fs::path here = folderOfThisCode(); !here.empty()) candidates.push_back(here / kModuleName);
    candidates.push_back(fs::path(RAY_MODULE_INSTALL_DIR) / kModuleName);
    candidates.push_back(fs::path(RAY_MODULE_BUILD_DIR) / kModuleName);
    return candidates;
}

template <typename Function>
bool resolve(void* library, const char* name, Function& function) {
    function = reinterpret_cast<Function>(dlsym(library, name));
    return function != nullptr;
}

OiioModule loadModule() {
    OiioModule module;
    std::string tried;
    for (const fs::path& candidate : moduleCandidates()) {
        std::error_code ec;
        if (!fs::exists(candidate, ec)) {
            tried += (tried.empty() ? "" : ", ") + candidate.string();
            continue;
        }
        void* library = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!library) {
            module.failure = "cannot load " + candidate.string() + ": " + dlerror();
            return module;
        }
        if (resolve(library, RAY_OIIO_OPEN, module.open) && resolve(library, RAY_OIIO_READ_RGB, module.readRgb) &&
            resolve(library, RAY_OIIO_CLOSE, module.close) && resolve(library, RAY_OIIO_CAN_WRITE, module.canWrite) &&
            resolve(library, RAY_OIIO_WRITE, module.write))
            return module;
        module.failure = candidate.string() + " is not ray's OpenImageIO module (a symbol is missing)";
        return module;
    }
    module.failure = std::string("ray's OpenImageIO module ") + kModuleName + " was not found (looked for " + tried +
                     "); reinstall ray, or set RAY_OIIO_MODULE to its path";
    return module;
}

// Loaded once per process, on first use; later calls wait for the first.
const OiioModule& oiioModule() {
    static std::once_flag once;
    static OiioModule module;
    std::call_once(once, [] { module = loadModule(); });
    return module;
}

const OiioModule& requireModule(const fs::path& file) {
    const OiioModule& module = oiioModule();
    if (!module.failure.empty()) throw ImageError(file.string() + ": " + module.failure);
    return module;
}

}  // namespace

Image readImageWithOiio(const fs::path& file) {
    const OiioModule& module = requireModule(file);
    char error[1024] = "";
    void* handle = nullptr;
    RayOiioImageInfo info{};
    if (!module.open(file.c_str(), &handle, &info, error, sizeof error)) throw ImageError(file.string() + ": " + error);
    struct Closer {
        const OiioModule& module;
        void* handle;
        ~Closer() { module.close(handle); }
    } closer{module, handle};
    if (info.width < 0 || info.height < 0 || info.channels <= 0)  // zero sizes: checkDecodedImageSize
        throw ImageError(file.string() + ": image has no pixels");
    // The module's decoded floats, then the RGB image.
    checkDecodedImageSize(file, uint64_t(info.width), uint64_t(info.height), uint64_t(info.channels + 3) * sizeof(float));
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
