// libFuzzer target: a course JSON scene's text (SPEC §7; scene/json_scene_reader.h), through
// the loader (its textures and meshes read from a scratch project laid out as the course's),
// the BVH and packing, and a tiny reference render.
//
// Anything but a clean InputError (an uncaught exception, a sanitizer report, a hang, an
// allocation over libFuzzer's limit) is a crash. Seeds: the course's JSON scenes and
// tests/data/fuzz/json_scene (scripts/fuzz.sh); dictionary: fuzz/json_scene.dict.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz_support.h"
#include "scene_from_text.h"

namespace {

namespace fs = std::filesystem;

// project/scenes/fuzzed.json, with project/textures/board.png and project/meshes/tri.obj:
// the paths the course's scenes write ("textures/board.png", relative to the folder above
// the scene's).
const fs::path& sceneFile() {
    static const fs::path file = [] {
        const fs::path project = ray::fuzz::scratchFolder() / "project";
        fs::create_directories(project / "scenes");
        fs::create_directories(project / "textures");
        fs::create_directories(project / "meshes");
        std::error_code ignored;
        fs::copy_file(fs::path(RAY_SOURCE_DIR) / "scenes" / "textures" / "checker.png", project / "textures" / "board.png",
                      fs::copy_options::overwrite_existing, ignored);
        std::ofstream(project / "meshes" / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        return project / "scenes" / "fuzzed.json";
    }();
    return file;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string json(reinterpret_cast<const char*>(data), size);
    ray::LoadOptions options;
    ray::fuzz::loadPackAndRender(json, sceneFile(), options);
    return 0;
}
