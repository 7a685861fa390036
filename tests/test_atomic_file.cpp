// Atomic file writes (core/atomic_file) and the clear messages of issue 16. The faults that
// need root (a full tmpfs, other users, kill -9) are in tests/fault_injection.sh.
#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>

#include <sys/stat.h>

#include "core/atomic_file.h"
#include "image/image.h"
#include "scene/mesh.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

fs::path freshFolder(const std::string& name) {
    fs::path dir = ray::test::outputDir() / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string contents(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

size_t entriesIn(const fs::path& dir) {
    size_t n = 0;
    for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++n;
    return n;
}

}  // namespace

TEST_CASE("writeFileAtomically writes, replaces and leaves nothing else in the folder", "[atomic_file]") {
    fs::path dir = freshFolder("atomic_replace");
    ray::writeFileAtomically(dir / "a.json", "first");
    CHECK(contents(dir / "a.json") == "first");
    ray::writeFileAtomically(dir / "a.json", "second, longer");
    CHECK(contents(dir / "a.json") == "second, longer");
    CHECK(entriesIn(dir) == 1);
}

TEST_CASE("a write into a missing folder names the path and the system's reason", "[atomic_file]") {
    fs::path target = freshFolder("atomic_missing") / "no" / "such" / "out.json";
    try {
        ray::writeFileAtomically(target, "x");
        FAIL("no error");
    } catch (const ray::FileWriteError& e) {
        CHECK_THAT(e.what(), Contains(target.string()));
        CHECK_THAT(e.what(), Contains("No such file or directory"));
    }
}

TEST_CASE("an encoder that fails leaves the old file and no temporary file", "[atomic_file]") {
    fs::path dir = freshFolder("atomic_encoder_fails");
    ray::writeFileAtomically(dir / "img.png", "old");
    fs::path seen;
    CHECK_THROWS_WITH(ray::writeFileAtomicallyVia(dir / "img.png",
                                                  [&](const fs::path& tmp) {
                                                      seen = tmp;
                                                      std::ofstream(tmp) << "half";
                                                      throw std::runtime_error("encoder failed");
                                                  }),
                      "encoder failed");
    CHECK(seen.parent_path() == dir);  // beside the target: the rename stays on one file system
    CHECK(seen.extension() == ".png");  // encoders choose the format by extension
    CHECK(contents(dir / "img.png") == "old");
    CHECK(entriesIn(dir) == 1);
}

TEST_CASE("writeImage goes through the atomic writer for memory and path encoders", "[atomic_file]") {
    fs::path dir = freshFolder("atomic_images");
    ray::Image image(4, 3);
    image.set(1, 1, {1, 0.5, 0.25});
    for (const char* name : {"a.png", "a.ppm", "a.exr", "a.hdr", "a.tif", "a.jpg"}) {
        ray::writeImage(image, dir / name);
        ray::Image back = ray::readImage(dir / name);
        CHECK(back.width == 4);
        CHECK(back.height == 3);
    }
    CHECK(entriesIn(dir) == 6);
    CHECK_THROWS_WITH(ray::writeImage(image, dir / "missing" / "a.png"), Contains("No such file or directory"));
}

TEST_CASE("a folder given as the scene file says so", "[atomic_file][loader]") {
    fs::path dir = freshFolder("scene_is_folder");
    CHECK_THROWS_WITH(ray::loadScene(dir), Contains("is a folder, not a scene file"));
}

TEST_CASE("an OBJ parse error names the file and line on every line of the message", "[atomic_file][loader]") {
    fs::path obj = freshFolder("obj_error") / "bad.obj";
    std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nf 0 0 0\n";
    try {
        ray::loadObjMesh(obj);
        FAIL("no error");
    } catch (const ray::InputError& e) {
        std::istringstream lines(e.what());
        std::string line;
        std::getline(lines, line);
        CHECK_THAT(line, Contains(obj.string() + ":3: error:"));
        while (std::getline(lines, line)) CHECK_THAT(line, Contains(obj.string()));
    }
}

TEST_CASE("a texture that is a FIFO is refused without opening it", "[atomic_file]") {
    fs::path fifo = freshFolder("fifo_texture") / "t.png";
    REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
    CHECK_THROWS_WITH(ray::readImage(fifo), Contains("not a regular file (a FIFO)"));
    CHECK_THROWS_WITH(ray::readImage("/dev/zero"), Contains("not a regular file"));
}
