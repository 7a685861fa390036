// Comparing the OpenCL kernel with the host reference renderer, for the kernel-versus-host
// tests of every feature.
#pragma once

#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <set>
#include <string>

#include "devices/renderer.h"
#include "opencl/opencl_device.h"
#include "opencl/opencl_renderer.h"
#include "reference/reference_renderer.h"
#include "scene/scene_loader.h"
#include "test_support.h"

namespace ray::test {

// The course's refraction and area-light scenes, which the optics test (test_optics.cpp)
// compares kernel with host at 96×72 with the default settings, as the corpus test
// (test_kernel_vs_host.cpp) would: that test leaves them to it rather than render them twice
// (shadow_test_area alone took 30 s of either).
inline const std::set<std::string> kOpticsCourseScenes = {
    "refract.xml",       "refract2.xml",      "refract_box.xml",        "refract_whitted.xml",
    "ayidi_refract.xml", "area_light_1.xml",  "area_light_2.xml",       "shadow_test_area.xml",
    "refract_whitted_area.xml"};
constexpr int kOpticsWidth = 96, kOpticsHeight = 72;

// The first OpenCL CPU device (PoCL here), or nullopt: callers then skip(). RAY_TEST_DEVICE
// (a --device value: gpu, an index) runs the kernel-versus-host tests on another device
// instead (scripts/gpu_check.sh).
inline std::optional<OpenClDevice> cpuDevice() {
    const char* chosen = std::getenv("RAY_TEST_DEVICE");
    try {
        return selectOpenClDevices(chosen && *chosen ? chosen : "cpu").front();
    } catch (const DeviceError&) {
        return std::nullopt;
    }
}

// Holds `image` to `expected` as the kernel-versus-host tests do: >= 99% of pixels within
// 3/255 (or `minimumWithin`, for the few scenes whose callers say why) and a mean error
// <= 1/255, printing the figures. A failure leaves both images and their difference in the
// test output folder's `folder`, named after `label` and the two names.
inline void checkImagesAgree(const Image& image, const Image& expected, const std::string& label,
                             const std::string& folder, const std::string& imageName, const std::string& expectedName,
                             double minimumWithin = 0.99) {
    namespace fs = std::filesystem;
    ImageDifference d = compare8bit(image, expected, 3);
    std::printf("%-40s %8.3f%% within 3/255, mean error %.4f/255, max %d\n", label.c_str(), d.fractionWithin * 100,
                d.meanAbsError, d.maxError);
    std::fflush(stdout);
    bool ok = d.fractionWithin >= minimumWithin && d.meanAbsError <= 1.0;
    if (!ok) {
        fs::path dir = outputDir() / folder;
        fs::create_directories(dir);
        writeImage(image, dir / (label + "_" + imageName + ".png"));
        writeImage(expected, dir / (label + "_" + expectedName + ".png"));
        if (image.width == expected.width && image.height == expected.height)
            writeImage(differenceImage(image, expected), dir / (label + "_difference.png"));
        UNSCOPED_INFO("images written to " << dir.string());
    }
    INFO(label << ": " << d.fractionWithin * 100 << "% within 3/255, mean error " << d.meanAbsError << "/255");
    CHECK(ok);
}

// Renders the scene both ways and holds the kernel to the host (checkImagesAgree).
inline void compareKernelWithHost(const OpenClDevice& device, const Scene& scene, const RenderSettings& settings,
                                  const std::string& label, double minimumWithin = 0.99) {
    Image host = renderReference(scene, settings);
    Image kernel = renderOpenCl(device, scene, settings, {}, nullptr);
    checkImagesAgree(kernel, host, label, "kernel_vs_host", "kernel", "host", minimumWithin);
}

// The scene loaded quietly (warnings are the loader tests' business).
inline Scene loadSceneQuietly(const std::filesystem::path& sceneFile) {
    LoadOptions load;
    load.warn = [](const std::string&) {};
    return loadScene(sceneFile, load);
}

inline void compareKernelWithHost(const OpenClDevice& device, const std::filesystem::path& sceneFile,
                                  const RenderSettings& settings, const std::string& label,
                                  double minimumWithin = 0.99) {
    compareKernelWithHost(device, loadSceneQuietly(sceneFile), settings, label, minimumWithin);
}

}  // namespace ray::test
