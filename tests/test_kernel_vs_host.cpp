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
#include "scene/scene_loader.h"

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
// lower share of close pixels. Measured with the course's per-quadrant subdivision
// (docs/conventions.md, "Antialiasing"), which leaves quadrants that match their
// neighbours at one sample, so that a flipped sample weighs up to 1/4 of a pixel rather
// than 1/64: 98.3, 96.2, 94.3, 93.0, 89.3 and 96.5% (93.8, 96.0, 97.3, 98.2 and 97.8% for
// 10, 9, 8, 7 and the plane with the earlier rule, which subdivided every quadrant of a
// busy square):
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

// The course scenes whose pixels cost a hundred times the others' (test::isCostlyCourseScene)
// are compared at 48×36: recursiveSpheres4_area took 128 s of this test's 315 at 96×72 (2
// cores, ctest -j2), dof-recursiveSpheres4 20 s. At 48×36 each still fails when the kernel
// breaks the convention it tests: area lights twice their size (cl/shading/optics.cl areaLightPoint,
// 2a and 2b: 90.6% of the pixels within 3/255) and a lens of twice the radius (cl/render/camera.cl
// cameraRay: 94.6%), while recursiveSpheres4 (neither) stays at 99.9%.
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
    std::vector<fs::path> scenes = test::courseScenes(*shared);
    int compared = 0, elsewhere = 0;
    for (const fs::path& file : scenes) {
        const std::string name = file.filename().string();
        if (test::kOpticsCourseScenes.count(name)) {
            ++elsewhere;  // compared with these very settings by the optics test (test_optics.cpp)
            continue;
        }
        RenderSettings settings = test::isCostlyCourseScene(name) ? test::settingsFromOptions("", 48, 36)
                                                                  : test::settingsFromOptions("", 96, 72);
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
    std::printf("compared %d course scenes (and %d in the optics test)\n", compared, elsewhere);
    CHECK(elsewhere == int(test::kOpticsCourseScenes.size()));
    CHECK(compared + elsewhere >= 200);
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

TEST_CASE("kernel matches host with stratified sampling and depth of field", "[kernel][kvh][dof]") {
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
    // The course's lens (the default: a 5×5 grid, SPEC §3) as the course renders it, without
    // antialiasing, and under stratified samples; the random disk (--dof disk).
    const std::map<std::string, RenderSettings> lenses = {
        {"course", test::settingsFromOptions("--aa off", kWidth, kHeight)},
        {"course_stratified", test::settingsFromOptions("--aa stratified --samples 4 --seed 7", kWidth, kHeight)},
        {"disk", test::settingsFromOptions("--aa stratified --samples 9 --seed 7 --dof disk", kWidth, kHeight)}};
    for (const auto& [lens, lensSettings] : lenses) {
        SECTION("depth_of_field.xml, " + lens) {
            compareKernelWithHost(*device, test::scenesDir() / "depth_of_field.xml", lensSettings,
                                  "dof_" + lens + "_depth_of_field");
        }
    }
    auto shared = test::sharedDir();
    if (!shared) {
        test::skip("../shared/cs123 is absent: no course depth-of-field scenes");
        return;
    }
    for (const char* scene : {"dof.xml", "dof-mirror_depth.xml"}) {
        for (const char* lens : {"course", "disk"}) {
            SECTION(std::string(scene) + ", " + lens) {
                compareKernelWithHost(*device, *shared / "cs123" / "scenes" / scene, lenses.at(lens),
                                      std::string("dof_") + lens + "_" + fs::path(scene).stem().string());
            }
        }
    }
}

// Reflected rays that bounce four times between the facing, textured mirror cubes of the
// course's dof.xml, through the pinhole (its PENDING.tsv options without the lens): each
// bounce's secondary ray must start on its own line (offsetAlongRay in cl/shading/shading.cl). A
// start moved along the normal alone shifted each next hit by about two texels, and the
// kernel was within 3/255 of the host on 98.4% of these pixels (99.8% on its own line).
TEST_CASE("kernel matches host between facing textured mirrors", "[kernel][kvh][mirrors]") {
    auto device = cpuDevice();
    if (!device) {
        test::skip("no OpenCL CPU device (install pocl-opencl-icd)");
        return;
    }
    auto shared = test::sharedDir();
    if (!shared) {
        test::skip("../shared/cs123 is absent: no dof.xml");
        return;
    }
    RenderSettings settings = test::settingsFromOptions("--aa off --no-dof --texture-filter course", kWidth, kHeight);
    compareKernelWithHost(*device, *shared / "cs123" / "scenes" / "dof.xml", settings, "facing_mirrors_dof");
}

// --course-meshes (docs/conventions.md, meshes): both renderers key mesh hits by
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

// Coincident surfaces (SPEC §4): the primitive listed last wins an exact tie, in both
// renderers, whatever order the BVH visits them in. Two identical cubes (red, then blue)
// tie on every face; a slab's top is flush with eight squares listed before it and eight
// after (the chessboard's case), so ties go both ways through the BVH's leaves; a csg
// union (yellow) listed after a cyan cube whose faces are its cube operand's.
TEST_CASE("kernel and host give coincident faces to the primitive listed last", "[kernel][kvh][ties]") {
    auto device = cpuDevice();
    if (!device) {
        test::skip("no OpenCL CPU device (install pocl-opencl-icd)");
        return;
    }
    auto cube = [](const std::string& transform, const std::string& color) {
        return "<transblock>" + transform + R"(<object type="primitive" name="cube"><diffuse )" + color +
               "/></object></transblock>\n";
    };
    const std::string red = R"(r="0.9" g="0.1" b="0.1")", blue = R"(r="0.1" g="0.1" b="0.9")";
    std::string squares[2];
    for (int row = 0; row < 2; ++row)
        for (int column = 0; column < 8; ++column)
            squares[row] += cube(R"(<translate x=")" + std::to_string(column - 3.5) + R"(" y="-1" z=")" +
                                     std::to_string(row * 2 - 1.5) + R"("/><scale x="1" y="0.5" z="1"/>)",
                                 (row + column) % 2 ? R"(r="0.9" g="0.9" b="0.9")" : R"(r="0.2" g="0.2" b="0.2")");
    const std::string xml = R"(<scenefile>
<cameradata><pos x="0" y="3" z="6"/><focus x="0" y="0" z="0"/><up x="0" y="1" z="0"/><heightangle v="50"/></cameradata>
<lightdata><id v="0"/><type v="directional"/><color r="1" g="1" b="1"/><direction x="-0.3" y="-1" z="-0.5"/></lightdata>
<object type="tree" name="root">
)" + cube(R"(<translate x="-1.5" y="0.5" z="0"/>)", red) +
                            cube(R"(<translate x="-1.5" y="0.5" z="0"/>)", blue) + squares[0] +
                            cube(R"(<translate x="0" y="-1" z="0"/><scale x="8" y="0.5" z="8"/>)",
                                 R"(r="0.1" g="0.6" b="0.1")") +
                            squares[1] + cube(R"(<translate x="1.5" y="0.5" z="0"/>)", R"(r="0.1" g="0.8" b="0.8")") +
                            R"(<transblock><translate x="1.5" y="0.5" z="0"/><object type="csg" operation="union">
  <transblock><object type="primitive" name="cube"><diffuse r="0.9" g="0.9" b="0.1"/></object></transblock>
  <transblock><scale x="0.5" y="0.5" z="0.5"/><object type="primitive" name="sphere"><diffuse r="0.9" g="0.9" b="0.1"/></object></transblock>
 </object></transblock>
</object>
</scenefile>)";
    LoadOptions options;
    options.warn = [](const std::string&) {};
    const Scene scene = loadSceneFromText(xml, "ties.xml", options);
    RenderSettings settings = test::settingsFromOptions("--aa off", 96, 72);
    compareKernelWithHost(*device, scene, settings, "coincident_faces");

    // Both renderers show the blue cube (listed after the red one) and the yellow csg object
    // (listed after the cyan cube) where they coincide, and the green slab shows through where
    // the squares listed before it lie.
    Image host = renderReference(scene, settings);
    Image kernel = renderOpenCl(*device, scene, settings, {}, nullptr);
    for (const Image* image : {&host, &kernel}) {
        int red = 0, blue = 0, green = 0, yellow = 0, cyan = 0;
        for (size_t p = 0; p < image->rgb.size(); p += 3) {
            const float r = image->rgb[p], g = image->rgb[p + 1], b = image->rgb[p + 2];
            red += r > 2 * g && r > 2 * b;
            blue += b > 2 * r && b > 2 * g;
            green += g > 2 * r && g > 2 * b;
            yellow += r > 2 * b && g > 2 * b;
            cyan += g > 2 * r && b > 2 * r;
        }
        INFO((image == &host ? "host" : "kernel") << ": red " << red << ", blue " << blue << ", green " << green
                                                  << ", yellow " << yellow << ", cyan " << cyan);
        CHECK(red == 0);
        // The kernel finds a csg operand's crossing from an origin moved next to it
        // (cl/geometry/csg.cl csgCrossing), so in float the cyan cube's face and the csg object's
        // are not always at exactly the same t: rounding decides a few of those pixels.
        if (image == &host) CHECK(cyan == 0);
        else CHECK(cyan * 4 < yellow);
        CHECK(blue > 100);
        CHECK(yellow > 100);
        CHECK(green > 100);  // the slab, between the squares listed before it
    }
}
