// Trilinear texture filtering (host/reference/texture_filtering.h): mipmap levels (sizes, box-filter
// averages, 8-bit rounding, the kernel's layout), the footprint and level selection, and
// the kernel against the reference with --texture-filter bilinear and trilinear.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "kernel_comparison.h"
#include "scene/mesh.h"
#include "scene/scene_loader.h"
#include "opencl/scene_packing.h"
#include "test_support.h"
#include "reference/texture_filtering.h"
#include "reference/texture_sampling.h"

using namespace ray;

namespace {

// A w×h image whose red channel is x/255 and green y/255 (8-bit values, as a PNG gives).
Image ramp(int w, int h) {
    Image image(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) image.set(x, y, {x / 255.0, y / 255.0, 1.0});
    return image;
}

}  // namespace

TEST_CASE("mipmaps: halved sizes down to 1×1, odd sizes rounded down", "[texture_filter]") {
    std::vector<Image> levels = buildMipLevels(ramp(8, 4));
    REQUIRE(levels.size() == 3);  // 4×2, 2×1, 1×1
    CHECK((levels[0].width == 4 && levels[0].height == 2));
    CHECK((levels[1].width == 2 && levels[1].height == 1));
    CHECK((levels[2].width == 1 && levels[2].height == 1));

    std::vector<Image> odd = buildMipLevels(ramp(5, 3));
    REQUIRE(odd.size() == 2);  // 2×1, 1×1
    CHECK((odd[0].width == 2 && odd[0].height == 1));
    CHECK(buildMipLevels(ramp(1, 1)).empty());
    CHECK(buildMipLevels(ramp(1, 4)).size() == 2);  // 1×2, 1×1
}

TEST_CASE("mipmaps: each texel is the rounded mean of its 2×2 block", "[texture_filter]") {
    std::vector<Image> levels = buildMipLevels(ramp(8, 4));
    // Level 1, texel (1, 0): columns 2, 3 and rows 0, 1 of the image: red (2+3)/2 = 2.5 → 3
    // (8-bit rounding, half away from zero), green (0+1)/2 = 0.5 → 1, blue stays 1.
    Vec3 c = levels[0].at(1, 0);
    CHECK(c.x * 255 == Approx(3).margin(1e-4));
    CHECK(c.y * 255 == Approx(1).margin(1e-4));
    CHECK(c.z == Approx(1).margin(1e-6));
    // The 1×1 level averages everything: a uniform image stays uniform at every level.
    Image flat(16, 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) flat.set(x, y, {100 / 255.0, 50 / 255.0, 0});
    for (const Image& level : buildMipLevels(flat)) CHECK(level.at(0, 0).x * 255 == Approx(100).margin(1e-4));
    // A checkerboard of black and white averages to mid gray (127.5 → 128) at 1×1.
    Image checker(4, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) checker.set(x, y, Vec3{1, 1, 1} * double((x + y) % 2));
    CHECK(buildMipLevels(checker).back().at(0, 0).x * 255 == Approx(128).margin(1e-4));
}

TEST_CASE("mipmaps: packed after the image in the texel buffer, level count in RayTexture.levels", "[texture_filter]") {
    Scene scene;
    scene.primitives.push_back(PrimitiveInstance{});  // a unit cube with material 0
    scene.materials.push_back(Material{});
    scene.images.push_back(ramp(8, 4));
    RenderSettings nearest = test::settingsFromOptions("--aa off", 8, 8);
    PackedScene plain = packScene(scene, nearest);
    CHECK(plain.textures[0].levels == 1);
    CHECK(plain.texels.size() == 8 * 4);

    RenderSettings trilinear = test::settingsFromOptions("--aa off --texture-filter trilinear", 8, 8);
    PackedScene mipmapped = packScene(scene, trilinear);
    CHECK(mipmapped.textures[0].levels == 4);
    CHECK(mipmapped.texels.size() == 32 + 8 + 2 + 1);
    // Level 1 texel (1, 0) (see above) follows the image's 32 texels.
    CHECK(int(mipmapped.texels[32 + 1].x) == 3);
    CHECK(int(mipmapped.texels[32 + 1].y) == 1);
    gpu::RayRenderParams params = makeRenderParams(scene, trilinear, mipmapped);
    CHECK((params.features & RAY_FEATURE_TRILINEAR) != 0);
    CHECK(params.pixelSpreadAngle == Approx(pixelSpreadAngle(scene.camera.heightAngleDegrees, 8)));
}

TEST_CASE("footprint and level selection", "[texture_filter]") {
    const double alpha = pixelSpreadAngle(90, 100);  // 2·tan 45° / 100
    CHECK(alpha == Approx(0.02));
    Affine identity;
    SECTION("head-on: α·t, stretched by the object's scale and the UV density") {
        CHECK(textureFootprint(alpha, 10, {0, 0, -1}, {0, 0, 1}, identity, 1) == Approx(0.2));
        Affine halfSize = Affine::scaling({0.5, 0.5, 0.5});  // world-to-object of an object scaled ×2
        CHECK(textureFootprint(alpha, 10, {0, 0, -1}, {0, 0, 1}, halfSize, 1) == Approx(0.1));
        CHECK(textureFootprint(alpha, 10, {0, 0, -1}, {0, 0, 1}, identity, 2 / std::numbers::pi) ==
              Approx(0.4 / std::numbers::pi));
    }
    SECTION("oblique: divided by cos θ, clamped at grazing angles") {
        Vec3 d = normalize(Vec3{1, 0, -1});
        CHECK(textureFootprint(alpha, 10, d, {0, 0, 1}, identity, 1) == Approx(0.2 * std::sqrt(2.0)));
        CHECK(textureFootprint(alpha, 10, {1, 0, 0}, {0, 0, 1}, identity, 1) == Approx(0.2 / kMinFootprintCos));
    }
    SECTION("the stretch is the largest within the tangent plane, not along the normal") {
        Affine flat = Affine::scaling({1.0 / 100, 100, 1.0 / 50});  // a plane scaled 100 × 0.01 × 50
        CHECK(textureFootprint(alpha, 10, {0, -1, 0}, {0, 1, 0}, flat, 1) == Approx(0.2 / 50));
    }
    SECTION("level: log2 of the footprint in texels, clamped to the pyramid") {
        // 64 texels, repeated 2×: a footprint of 1/128 is one texel (level 0), 1/32 four.
        CHECK(mipLevel(1.0 / 128, 64, 64, 2, 2, 7) == Approx(0));
        CHECK(mipLevel(1.0 / 32, 64, 64, 2, 2, 7) == Approx(2));
        CHECK(mipLevel(std::sqrt(2.0) / 32, 64, 64, 2, 2, 7) == Approx(2.5));
        CHECK(mipLevel(1.0 / 1024, 64, 64, 2, 2, 7) == 0);  // magnified: the image itself
        CHECK(mipLevel(100, 64, 64, 2, 2, 7) == 6);        // the 1×1 level at most
        CHECK(mipLevel(1.0 / 32, 64, 16, 1, 4, 7) == Approx(1));  // the larger of u, v texel rates
    }
    SECTION("trilinear: level 0 is bilinear, the top level the average") {
        Image checker(4, 4);
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x) checker.set(x, y, Vec3{1, 1, 1} * double((x + y) % 2));
        MipPyramid pyramid = buildMipPyramid(checker);
        REQUIRE(pyramid.levels.size() == 3);
        // (0.375, 0.875) is the centre of texel (1, 0), which is white.
        CHECK(sampleTrilinear(pyramid, 0.375, 0.875, 1, 1, 1e-3).x == Approx(1));
        CHECK(sampleTrilinear(pyramid, 0.375, 0.875, 1, 1, 10).x * 255 == Approx(128).margin(1e-4));
        // Footprint of 2 texels: level 1 (2×2 of mid gray) exactly.
        CHECK(sampleTrilinear(pyramid, 0.375, 0.875, 1, 1, 0.5).x * 255 == Approx(128).margin(1e-4));
        // Between levels 0 and 1: the mix.
        CHECK(sampleTrilinear(pyramid, 0.375, 0.875, 1, 1, std::sqrt(2.0) / 4).x ==
              Approx(0.5 * 1 + 0.5 * 128 / 255.0));
    }
}

TEST_CASE("the course filter puts texel corners at integer coordinates", "[texture_filter]") {
    Image image = ramp(4, 2);  // red = column/255, green = row/255
    // (u, v) = (0.25, 1): s·W = 1, (1 − t)·H = 0: exactly texel (1, 0), no half-texel shift.
    Vec3 atCorner = sampleCourseBilinear(image, 0.25, 0.999999999, 1, 1);
    CHECK(atCorner.x * 255 == Approx(1).margin(1e-6));
    CHECK(atCorner.y * 255 == Approx(0).margin(1e-6));
    // Halfway between columns 1 and 2 and between rows 0 and 1.
    Vec3 between = sampleCourseBilinear(image, 0.375, 0.75, 1, 1);
    CHECK(between.x * 255 == Approx(1.5).margin(1e-6));
    CHECK(between.y * 255 == Approx(0.5).margin(1e-6));
    // The centre-aligned filter reads the same point half a texel further on.
    Vec3 centred = sampleBilinear(image, 0.375 + 0.125, 0.75 - 0.25, 1, 1);
    CHECK(centred.x == Approx(between.x).margin(1e-9));
    CHECK(centred.y == Approx(between.y).margin(1e-9));
    // Past the last column it wraps to the first: x = 3.5 mixes columns 3 and 0.
    CHECK(sampleCourseBilinear(image, 0.875, 0.999999999, 1, 1).x * 255 == Approx(1.5).margin(1e-6));
}

TEST_CASE("kernel matches host with bilinear and trilinear filtering", "[kernel][kvh][texture_filter]") {
    auto device = test::cpuDevice();
    if (!device) {
        test::skip("no OpenCL CPU device (install pocl-opencl-icd)");
        return;
    }
    const auto scene = test::scenesDir() / "texture_filtering.xml";
    for (const char* filter : {"bilinear", "trilinear", "course"}) {
        SECTION(filter) {
            RenderSettings settings =
                test::settingsFromOptions(std::string("--aa off --texture-filter ") + filter, 160, 120);
            test::compareKernelWithHost(*device, scene, settings, std::string("texture_filtering_") + filter);
        }
    }
    SECTION("trilinear on the textured primitives") {
        RenderSettings settings = test::settingsFromOptions("--aa off --texture-filter trilinear", 160, 120);
        test::compareKernelWithHost(*device, test::scenesDir() / "texture_sphere.xml", settings,
                                    "texture_sphere_trilinear");
    }
}
