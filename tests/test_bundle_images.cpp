// The GPU bundle's image check (scripts/gpu_bundle.sh, scripts/gpu_check.sh): the images
// that PoCL's CPU device rendered when the bundle was made, rendered again on the device
// under test (RAY_TEST_DEVICE) and held to them as the kernel-versus-host tests hold the
// kernel to the host. Hidden ([.]): it runs only when asked for by its tag, with
// RAY_BUNDLE_DIR naming a bundle.
//
// The bundle's cpu-images/list.tsv has a line an image: the scene (relative to the
// bundle), width, height, ray's options and the PNG (relative to the bundle), tab-separated.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "kernel_comparison.h"

namespace fs = std::filesystem;
using namespace ray;

namespace {

struct BundleImage {
    std::string scene, options, image;
    int width = 0, height = 0;
};

std::vector<BundleImage> readBundleList(const fs::path& list) {
    std::ifstream in(list);
    if (!in) throw std::runtime_error(list.string() + ": cannot be read (make the bundle with scripts/gpu_bundle.sh)");
    std::vector<BundleImage> images;
    int lineNumber = 0;
    for (std::string line; std::getline(in, line);) {
        ++lineNumber;
        if (line.empty() || line[0] == '#') continue;
        std::vector<std::string> fields;
        std::stringstream cells(line);
        for (std::string cell; std::getline(cells, cell, '\t');) fields.push_back(cell);
        if (fields.size() != 5)
            throw std::runtime_error(list.string() + ":" + std::to_string(lineNumber) +
                                     ": expected 5 tab-separated fields (scene, width, height, options, image)");
        images.push_back({fields[0], fields[3], fields[4], std::stoi(fields[1]), std::stoi(fields[2])});
    }
    return images;
}

}  // namespace

TEST_CASE("the device renders the bundle's CPU images", "[.][bundle]") {
    const char* bundle = std::getenv("RAY_BUNDLE_DIR");
    if (!bundle || !*bundle) {
        test::skip("RAY_BUNDLE_DIR names no bundle (scripts/gpu_bundle.sh makes one)");
        return;
    }
    auto device = test::cpuDevice();  // RAY_TEST_DEVICE chooses the device under test
    if (!device) {
        test::skip("no OpenCL device of the kind RAY_TEST_DEVICE names");
        return;
    }
    std::printf("device: %s\n", device->name.c_str());
    const fs::path dir = bundle;
    const std::vector<BundleImage> images = readBundleList(dir / "cpu-images" / "list.tsv");
    REQUIRE(!images.empty());
    for (const BundleImage& entry : images) {
        const std::string label = fs::path(entry.scene).stem().string();
        SECTION(label) {
            RenderSettings settings = test::settingsFromOptions(entry.options, entry.width, entry.height);
            Image rendered = renderOpenCl(*device, test::loadSceneQuietly(dir / entry.scene), settings, {}, nullptr);
            // Through the PNG writer and reader, as the shipped image went: both sides then
            // hold the same 8-bit values.
            const fs::path written = test::outputDir() / "bundle_images" / (label + ".png");
            fs::create_directories(written.parent_path());
            writeImage(rendered, written);
            test::checkImagesAgree(readImage(written), readImage(dir / entry.image), label, "bundle_images",
                                   "device", "cpu");
        }
    }
}
