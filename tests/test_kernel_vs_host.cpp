// The OpenCL kernel against the host reference renderer, scene by scene: every bundled
// scene and the course scenes that have reference renders, at small sizes, on the first
// OpenCL CPU device (PoCL here).
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "opencl_device.h"
#include "opencl_renderer.h"
#include "reference_renderer.h"
#include "renderer.h"
#include "scene_loader.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using namespace ray;

constexpr int kWidth = 160, kHeight = 120;

std::optional<OpenClDevice> cpuDevice() {
    try {
        return selectOpenClDevices("cpu").front();
    } catch (const DeviceError&) {
        return std::nullopt;
    }
}

// Renders the scene both ways and holds the kernel to ≥ 99% of pixels within 3/255 and a
// mean error ≤ 1/255. A failure leaves both images and their difference in the test
// output folder.
void compareKernelWithHost(const OpenClDevice& device, const fs::path& sceneFile, const RenderSettings& settings,
                           const std::string& label) {
    LoadOptions load;
    load.warn = [](const std::string&) {};
    Scene scene = loadScene(sceneFile, load);
    Image host = renderReference(scene, settings);
    Image kernel = renderOpenCl(device, scene, settings, {}, nullptr);
    test::ImageDifference d = test::compare8bit(kernel, host, 3);
    INFO(label << ": " << d.fractionWithin * 100 << "% within 3/255, mean error " << d.meanAbsError
               << "/255, max " << d.maxError);
    std::printf("%-40s %8.3f%% within 3/255, mean error %.4f/255, max %d\n", label.c_str(), d.fractionWithin * 100,
                d.meanAbsError, d.maxError);
    std::fflush(stdout);
    bool ok = d.fractionWithin >= 0.99 && d.meanAbsError <= 1.0;
    if (!ok) {
        fs::path dir = test::outputDir() / "kernel_vs_host";
        fs::create_directories(dir);
        writeImage(kernel, dir / (label + "_kernel.png"));
        writeImage(host, dir / (label + "_host.png"));
        writeImage(test::differenceImage(kernel, host), dir / (label + "_difference.png"));
        UNSCOPED_INFO("images written to " << dir.string());
    }
    CHECK(ok);
}

}  // namespace

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
