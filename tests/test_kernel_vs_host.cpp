// The OpenCL kernel against the host reference renderer, scene by scene: every bundled
// scene, every course scene and the course scenes that have reference renders (with their
// options), at small sizes, on the first OpenCL CPU device (PoCL here).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
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

// A bump-mapped mesh whose right half mirrors its texture coordinates: both renderers must
// turn the bitangent around there (host/scene/mesh.h uvHandedness).
TEST_CASE("kernel matches host on a bump-mapped mesh with mirrored texture coordinates", "[kernel][kvh]") {
    auto device = cpuDevice();
    if (!device) {
        test::skip("no OpenCL CPU device (install pocl-opencl-icd)");
        return;
    }
    RenderSettings settings = test::settingsFromOptions("", kWidth, kHeight);
    compareKernelWithHost(*device, test::testDataDir() / "scenes" / "bumped_mirrored_mesh.xml", settings,
                          "bumped_mirrored_mesh");
}

// Every scene of the course corpus, small, with the course's antialiasing (its default):
// the comparison that found the spot lights whose penumbra is wider than their cone and
// the float cancellation in the sphere test (spotlight_on_cheese 42%, recursiveSpheres10
// 76% of pixels within 3/255 before those fixes). A few scenes are chaotic at the pixel
// level, where float and double legitimately pick different surfaces, and are held to a
// lower share of close pixels. Measured with the course's per-quadrant subdivision (README,
// Conventions, "Antialiasing"), which leaves quadrants that match their neighbours at one
// sample, so that a flipped sample weighs up to 1/4 of a pixel rather than 1/64: 98.3, 96.2,
// 94.3, 93.0, 89.3 and 96.5% (93.8, 96.0, 97.3, 98.2 and 97.8% for 10, 9, 8, 7 and the plane
// with the earlier rule, which subdivided every quadrant of a busy square):
const std::map<std::string, double> kChaoticScenes = {
    // sub-pixel spheres by the thousand: which one a ray meets depends on the last bits
    {"recursiveSpheres6.xml", 0.97},
    {"recursiveSpheres7.xml", 0.95},
    {"recursiveSpheres8.xml", 0.93},
    {"recursiveSpheres9.xml", 0.92},
    {"recursiveSpheres10.xml", 0.88},
    // a fine checker seen through four glass balls: refraction magnifies texel boundaries
    {"ayidi_refract2_plane.xml", 0.95},
};

TEST_CASE("kernel matches host on every course scene", "[kernel][kvh][corpus]") {
    auto device = cpuDevice();
    if (!device) {
        test::skip("no OpenCL CPU device (install pocl-opencl-icd)");
        return;
    }
    auto shared = test::sharedDir();
    if (!shared) {
        test::skip("../shared/cs123 is absent: no course scenes");
        return;
    }
    std::vector<fs::path> scenes;
    for (const auto& entry : fs::directory_iterator(*shared / "cs123" / "scenes"))
        if (entry.path().extension() == ".xml") scenes.push_back(entry.path());
    std::sort(scenes.begin(), scenes.end());
    RenderSettings settings = test::settingsFromOptions("", 96, 72);
    int compared = 0;
    for (const fs::path& file : scenes) {
        const std::string name = file.filename().string();
        std::optional<Scene> scene;
        try {
            scene = test::loadSceneQuietly(file);
        } catch (const InputError&) {
            continue;  // the corpus test checks that these fail clearly, on both renderers
        }
        auto chaotic = kChaoticScenes.find(name);
        compareKernelWithHost(*device, *scene, settings, "corpus_" + file.stem().string(),
                              chaotic == kChaoticScenes.end() ? 0.99 : chaotic->second);
        ++compared;
    }
    std::printf("compared %d course scenes\n", compared);
    CHECK(compared >= 200);
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

// --course-meshes (README "Conventions", meshes): both renderers key mesh hits by
// t·|M⁻¹d|, place the hit point there and shade meshes with face normals. The course's
// pdiddy scene (a mesh scaled 3.5, so its hits move to 1/3.5 of their distance) with its
// PENDING.tsv options, and the bundled vase.
TEST_CASE("kernel matches host with the course's mesh distances", "[kernel][kvh][course-meshes]") {
    auto device = cpuDevice();
    if (!device) {
        test::skip("no OpenCL CPU device (install pocl-opencl-icd)");
        return;
    }
    SECTION("mesh_vase.xml") {
        RenderSettings settings = test::settingsFromOptions("--course-meshes", kWidth, kHeight);
        compareKernelWithHost(*device, test::scenesDir() / "mesh_vase.xml", settings, "course_meshes_mesh_vase");
    }
    auto shared = test::sharedDir();
    if (!shared) {
        test::skip("../shared/cs123 is absent: no pdiddy scene");
        return;
    }
    SECTION("pdiddy__cs1230-test_mesh.xml") {
        RenderSettings settings = test::settingsFromOptions(
            "--aa course --no-dof --texture-filter course --course-meshes", kWidth, kHeight);
        compareKernelWithHost(*device, *shared / "cs123" / "scenes" / "pdiddy__cs1230-test_mesh.xml", settings,
                              "course_meshes_pdiddy");
    }
}
