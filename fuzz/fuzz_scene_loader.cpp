// libFuzzer target: a scene file's XML text, through the loader (with textures read from
// files in a scratch folder), the BVH and packing, and a tiny reference render.
//
// Anything but a clean InputError (an uncaught exception, a sanitizer report, a hang, an
// allocation over libFuzzer's limit) is a crash. Seeds: the course scenes and ours
// (scripts/fuzz.sh); dictionary: fuzz/scene.dict.
#include <cstdint>
#include <filesystem>
#include <string>

#include "fuzz_support.h"
#include "scene_from_text.h"

namespace {

namespace fs = std::filesystem;

// A scene folder holding small textures under the names the course scenes use, so that
// `image/board.png`, `/course/cs123/data/image/board.png` and `checker.png` resolve.
const fs::path& sceneFolder() {
    static const fs::path folder = [] {
        fs::path scenes = ray::fuzz::scratchFolder() / "scenes";
        fs::create_directories(scenes / "image");
        const fs::path textures = fs::path(RAY_SOURCE_DIR) / "scenes" / "textures";
        std::error_code ignored;
        for (const char* name : {"board.png", "checker.png", "chessboard.png", "earth.png", "mandril.png"})
            fs::copy_file(textures / "checker.png", scenes / "image" / name, fs::copy_options::overwrite_existing, ignored);
        for (const char* name : {"uvgrid.png", "wood.png"})
            fs::copy_file(textures / name, scenes / "image" / name, fs::copy_options::overwrite_existing, ignored);
        return scenes;
    }();
    return folder;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string xml(reinterpret_cast<const char*>(data), size);
    ray::LoadOptions options;
    options.loadImages = true;
    ray::fuzz::loadPackAndRender(xml, sceneFolder() / "fuzzed.xml", options);
    return 0;
}
