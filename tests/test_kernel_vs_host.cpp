// The OpenCL kernel against the host reference renderer, scene by scene: every bundled
// scene and the course scenes that have reference renders, at small sizes, on the first
// OpenCL CPU device (PoCL here).
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "kernel_comparison.h"

namespace fs = std::filesystem;
using namespace ray;
using test::compareKernelWithHost;
using test::cpuDevice;

constexpr int kWidth = 160, kHeight = 120;

TEST_CASE("kernel matches host on every bundled scene", "[kernel][kvh]") {
    auto device = cpuDevice();
    if (!device) {
        test::skip("no OpenCL CPU device (install pocl-opencl-icd)");
        return;
    }
    std::vector<fs::path> scenes;
    for (const auto& entry : fs::directory_iterator(test::scenesDir()))
        if (entry.path().extension() == ".xml") scenes.push_back(entry.path());
    std::sort(scenes.begin(), scenes.end());
    REQUIRE(!scenes.empty());
    for (const fs::path& file : scenes) {
        SECTION(file.filename().string()) {
            RenderSettings settings = test::settingsFromOptions("", kWidth, kHeight);
            compareKernelWithHost(*device, file, settings, file.stem().string());
        }
    }
}

// No bundled scene combines a bump map with glass: here both renderers must agree that a
// bump map tilts the shading normal but leaves the entering/leaving decision to the surface.
TEST_CASE("kernel matches host on bump-mapped glass", "[kernel][kvh]") {
    auto device = cpuDevice();
    if (!device) {
        test::skip("no OpenCL CPU device (install pocl-opencl-icd)");
        return;
    }
    RenderSettings settings = test::settingsFromOptions("", kWidth, kHeight);
    compareKernelWithHost(*device, test::testDataDir() / "scenes" / "bumped_glass.xml", settings, "bumped_glass");
}

TEST_CASE("kernel matches host on the course scenes with reference renders", "[kernel][kvh]") {
    auto device = cpuDevice();
    auto shared = test::sharedDir();
    if (!device || !shared) {
        test::skip(!device ? "no OpenCL CPU device (install pocl-opencl-icd)" : "../shared/cs123 is absent");
        return;
    }
    const fs::path course = *shared / "cs123";
    for (const test::ReferenceCase& c : test::readReferenceIndex(course / "reference" / "INDEX.tsv")) {
        SECTION(c.scene) {
            RenderSettings settings = test::settingsFromOptions(c.options, kWidth, kHeight);
            compareKernelWithHost(*device, course / c.scene, settings, "course_" + fs::path(c.scene).stem().string());
        }
    }
}

TEST_CASE("kernel matches host with stratified sampling and depth of field", "[kernel][kvh]") {
    auto device = cpuDevice();
    if (!device) {
        test::skip("no OpenCL CPU device (install pocl-opencl-icd)");
        return;
    }
    // Both renderers draw the same jitter and lens samples (cl/random.h), so the images
    // agree as closely as the deterministic modes do.
    RenderSettings settings = test::settingsFromOptions("--aa stratified --samples 9 --seed 7", kWidth, kHeight);
    SECTION("showpiece.xml") {
        compareKernelWithHost(*device, test::scenesDir() / "showpiece.xml", settings, "stratified_showpiece");
    }
    auto shared = test::sharedDir();
    if (!shared) {
        test::skip("../shared/cs123 is absent: no depth-of-field scenes");
        return;
    }
    for (const char* scene : {"dof.xml", "dof-mirror_depth.xml"}) {
        SECTION(scene) {
            compareKernelWithHost(*device, *shared / "cs123" / "scenes" / scene, settings,
                                  std::string("dof_") + fs::path(scene).stem().string());
        }
    }
}
