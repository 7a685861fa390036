// Every scene of the course corpus (../shared/cs123/scenes) loads, or fails with the
// clear error SPEC §1 asks for. The failures are listed exactly, so that a regression in
// either direction shows.
#include <catch2/catch.hpp>

#include <algorithm>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "scene/scene_loader.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace {

struct ExpectedFailure {
    std::string where;  // "file.xml:LINE: error: "
    std::string what;   // a fragment of the message
};

// Meshes that are not public (cs123/README.md) and a primitive the course never had.
// (pikachu_head.xml's r="=0.1" loads, with a warning about the stray '='.)
const std::map<std::string, ExpectedFailure> kExpectedFailures = {
    {"dragon.xml", {"dragon.xml:72: error: ", "mesh file 'mesh/dragon.obj' not found"}},
    {"mesh.xml", {"mesh.xml:27: error: ", "mesh file '/course/cs123/data/mesh/dragon.obj' not found"}},
    {"piano.xml", {"piano.xml:42: error: ", "mesh file 'mesh/piano.obj' not found"}},
    {"PenroseTriangle.xml", {"PenroseTriangle.xml:58: error: ", "unknown primitive 'triangle'"}},
};

// The three texture files of the corpus that are not public (49 of 52 are).
const std::set<std::string> kMissingTextures = {
    "C:\\Users\\Public\\Pictures\\Sample Pictures\\earth.jpg",
    "C:\\Users\\Public\\Pictures\\Sample Pictures\\huo.jpg",
    "/course/cs123/data/image/terrian/grass.jpg",  // sic: test_bumpmap.xml misspells terrain
};

// The file name quoted in a "... file 'NAME' not found" warning.
std::string quotedFile(const std::string& warning) {
    size_t start = warning.find("file '");
    if (start == std::string::npos) return {};
    start += 6;
    return warning.substr(start, warning.find("' not found", start) - start);
}

}  // namespace

TEST_CASE("every course scene loads, or fails with a clear error", "[corpus]") {
    std::optional<fs::path> shared = ray::test::sharedDir();
    if (!shared) {
        ray::test::skip("../shared/cs123 is absent: the course corpus is not here");
        return;
    }
    std::vector<fs::path> scenes = ray::test::courseScenes(*shared);
    REQUIRE(scenes.size() == 215);

    std::map<std::string, std::string> failures;  // scene -> message
    std::set<std::string> missingTextures;
    std::vector<std::string> otherImageWarnings;
    size_t loaded = 0, withImages = 0;
    for (const fs::path& file : scenes) {
        std::string name = file.filename().string();
        ray::LoadOptions options;
        options.warn = [&](const std::string& warning) {
            if (warning.find("not found") != std::string::npos)
                missingTextures.insert(quotedFile(warning));
            else if (warning.find("image") != std::string::npos)
                otherImageWarnings.push_back(warning);
        };
        try {
            ray::Scene scene = ray::loadScene(file, options);
            ++loaded;
            if (!scene.images.empty()) ++withImages;
            for (const ray::Image& image : scene.images) CHECK_FALSE(image.empty());
        } catch (const ray::InputError& e) {
            failures[name] = e.what();
        }
    }

    std::set<std::string> failed, expected;
    for (const auto& [name, message] : failures) failed.insert(name);
    for (const auto& [name, failure] : kExpectedFailures) expected.insert(name);
    CHECK(failed == expected);
    for (const auto& [name, message] : failures) {
        INFO(message);
        auto it = kExpectedFailures.find(name);
        if (it == kExpectedFailures.end()) continue;
        CHECK(message.find(it->second.where) != std::string::npos);
        CHECK(message.find(it->second.what) != std::string::npos);
    }
    CHECK(loaded == 215 - kExpectedFailures.size());
    CHECK(withImages > 0);
    CHECK(missingTextures == kMissingTextures);
    CHECK(otherImageWarnings.empty());
}

// How long the load takes is bench/'s business (bench/bench.cpp renders recursiveSpheres10,
// load included): a test asserts what the load builds, never a time.
TEST_CASE("the deepest master recursion of the corpus flattens with shared materials", "[corpus]") {
    std::optional<fs::path> shared = ray::test::sharedDir();
    if (!shared) {
        ray::test::skip("../shared/cs123 is absent: the course corpus is not here");
        return;
    }
    ray::Scene scene = ray::loadScene(*shared / "cs123" / "scenes" / "recursiveSpheres10.xml");
    INFO("loaded " << scene.primitives.size() << " instances");
    CHECK(scene.primitives.size() > 2'000'000);
    // Masters share the material of the element they come from.
    CHECK(scene.materials.size() < 100);
}
