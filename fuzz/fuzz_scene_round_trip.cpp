// libFuzzer target: a scene's round trip. Text that loads as a scene document is saved as a
// scenefile (documentToText), which unedited must be the text itself, byte for byte (the
// save keeps the file: scene/document_splices.h); it is also written afresh
// (scene/canonical_writer.h, what a document made in code saves as), and that text loaded
// again must not differ from the first in anything a render reads
// (scene/scene_difference.h). What the savers write must load, and load to what was saved:
// a modeler's user saves and reopens all day.
//
// Anything but a clean InputError from the first load (or from saving what a file cannot
// hold) is a crash; so is a difference. Seeds: the course scenes and ours (scripts/fuzz.sh);
// dictionary: fuzz/scene.dict.
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>

#include "fuzz_support.h"
#include "scene/canonical_writer.h"
#include "scene/scene_difference.h"
#include "scene/scene_loader.h"

namespace {

std::string differingParts(const ray::SceneDifference& d) {
    std::string parts;
    for (const auto& [differs, name] : {std::pair{d.geometry, "geometry"}, {d.primitiveMaterials, "primitive materials"},
                                        {d.materials, "materials"}, {d.lights, "lights"}, {d.images, "images"},
                                        {d.globals, "globals"}, {d.camera, "camera"}})
        if (differs) parts += (parts.empty() ? "" : ", ") + std::string(name);
    return parts;
}

struct Loaded {
    ray::SceneDocument document;
    ray::Resources resources;
    ray::Scene scene;
};

// The text as a document and its flattened scene. Throws InputError.
Loaded load(const std::string& xml, const std::filesystem::path& file) {
    ray::LoadOptions options;
    options.loadImages = false;  // the textures' pixels are not the saver's concern
    options.maxPrimitives = 20000;
    options.warn = [](const std::string&) {};
    Loaded loaded;
    loaded.document = ray::loadSceneDocumentFromText(xml, file, options);
    loaded.scene = ray::flattenDocument(loaded.document, loaded.resources, options);
    return loaded;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::filesystem::path file = ray::fuzz::scratchFolder() / "round_trip.xml";
    const std::string text(reinterpret_cast<const char*>(data), size);
    Loaded first;
    std::string saved;
    try {
        first = load(text, file);
        if (ray::documentFileBytes(first.document, first.resources, file) != text)
            ray::fuzz::fail("the unedited save is not the file", "", text);
        saved = ray::CanonicalWriter(first.document, first.resources, file).document();
    } catch (const ray::InputError&) {
        return 0;  // not a scene, or one a file cannot hold: a clean refusal
    }
    Loaded second;
    try {
        second = load(saved, file);
    } catch (const ray::InputError& e) {
        ray::fuzz::fail("the saved scene does not load", e.what(), saved);
    }
    const ray::SceneDifference difference = ray::compareScenes(first.scene, second.scene);
    if (difference.any()) ray::fuzz::fail("the saved scene loads to another scene", differingParts(difference), saved);
    return 0;
}
