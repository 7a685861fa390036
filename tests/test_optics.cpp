// Refraction and area lights (issue 4): the shared geometry (host/reference/optics.h), the
// reference renderer's behaviour, and the kernel against the host on our scenes and the
// course's refraction and area-light scenes.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "app/cli.h"
#include "kernel_comparison.h"
#include "reference/optics.h"

namespace fs = std::filesystem;
using namespace ray;

TEST_CASE("Snell's law bends toward the normal entering a denser medium", "[optics]") {
    Vec3 n{0, 1, 0};
    Vec3 d = normalize(Vec3{1, -1, 0});  // 45° incidence
    Vec3 t;
    REQUIRE(refractDirection(d, n, 1.0, 1.5, t));
    double sinIn = std::sqrt(0.5), sinOut = std::hypot(t.x, t.z);
    CHECK(sinIn * 1.0 == Approx(sinOut * 1.5));
    CHECK(t.y < 0);
    CHECK(length(t) == Approx(1.0));
    // ior 1 on both sides: straight through.
    REQUIRE(refractDirection(d, n, 1.3, 1.3, t));
    CHECK(t.x == Approx(d.x));
    CHECK(t.y == Approx(d.y));
}

TEST_CASE("total internal reflection beyond the critical angle", "[optics]") {
    Vec3 n{0, 1, 0};
    Vec3 t;
    double critical = std::asin(1 / 1.5);
    Vec3 steep{std::sin(critical - 0.01), -std::cos(critical - 0.01), 0};
    Vec3 grazing{std::sin(critical + 0.01), -std::cos(critical + 0.01), 0};
    CHECK(refractDirection(steep, n, 1.5, 1.0, t));
    CHECK_FALSE(refractDirection(grazing, n, 1.5, 1.0, t));
}

TEST_CASE("the medium stack tracks nested objects", "[optics]") {
    MediumStack air;
    CHECK(air.current() == 1.0);
    MediumStack water = air.beyond(true, 1.33);
    CHECK(water.current() == 1.33);
    MediumStack glass = water.beyond(true, 1.5);
    CHECK(glass.before(false, 1.5) == 1.5);
    CHECK(glass.beyond(false, 1.5).current() == 1.33);  // leaving the glass: back in water
    CHECK(water.beyond(false, 1.33).current() == 1.0);
    // Leaving an object no entry recorded (a camera inside it): from its ior into air.
    CHECK(air.before(false, 1.7) == 1.7);
    CHECK(air.beyond(false, 1.7).current() == 1.0);
    // Deeper than kMaxMedia: the innermost entry is overwritten.
    MediumStack deep;
    for (int i = 0; i < MediumStack::kMaxMedia + 2; ++i) deep = deep.beyond(true, 1.0 + i);
    CHECK(deep.count == MediumStack::kMaxMedia);
    CHECK(deep.current() == 1.0 + MediumStack::kMaxMedia + 1);
}

TEST_CASE("area light samples cover the rectangle, one per cell", "[optics]") {
    Light light;
    light.type = LightType::Area;
    light.position = {1, 4, 2};
    light.direction = {0, -1, 0};  // width along +x, height along +z (optics.h)
    light.width = 2;
    light.height = 1;
    const int side = 4;
    for (int cell = 0; cell < side * side; ++cell) {
        Vec3 p = areaLightPoint(light, 0, cell, side, 17, 3, 5);
        CHECK(p.y == Approx(4.0));
        double a = (p.x - 1) / 2 + 0.5, b = (p.z - 2) / 1 + 0.5;  // in [0, 1)² across the rectangle
        CHECK(int(std::floor(a * side)) == cell % side);
        CHECK(int(std::floor(b * side)) == cell / side);
    }
    RenderSettings s;
    s.areaSamples = 16;
    CHECK(areaLightGridSide(s) == 4);
    s.areaSamples = 10;
    CHECK(areaLightGridSide(s) == 3);
    CHECK(parseCommandLine({"scene.xml", "--area-samples", "64"}).settings.areaSamples == 64);
    CHECK_THROWS_AS(parseCommandLine({"scene.xml", "--area-samples", "0"}), UsageError);
}

TEST_CASE("refraction switched off renders transparent materials opaque", "[optics]") {
    LoadOptions load;
    load.warn = [](const std::string&) {};
    Scene scene = loadScene(test::scenesDir() / "refraction.xml", load);
    RenderSettings on = test::settingsFromOptions("--aa off", 48, 36);
    RenderSettings off = test::settingsFromOptions("--aa off --no-refraction", 48, 36);
    Image withGlass = renderReference(scene, on);
    Image opaque = renderReference(scene, off);
    for (Material& m : scene.materials) m.transparent = {};
    Image noTransparency = renderReference(scene, on);
    CHECK(test::compare8bit(opaque, noTransparency, 0).fractionWithin == 1.0);
    CHECK(test::compare8bit(withGlass, opaque, 3).fractionWithin < 0.9);  // the glass shows
}

TEST_CASE("kernel matches host on the course's refraction and area-light scenes", "[kernel][kvh][optics]") {
    auto device = test::cpuDevice();
    auto shared = test::sharedDir();
    if (!device || !shared) {
        test::skip(!device ? "no OpenCL CPU device (install pocl-opencl-icd)" : "../shared/cs123 is absent");
        return;
    }
    // The corpus test (test_kernel_vs_host.cpp) leaves these scenes to this one.
    for (const std::string& scene : test::kOpticsCourseScenes) {
        SECTION(scene) {
            RenderSettings settings = test::settingsFromOptions("", test::kOpticsWidth, test::kOpticsHeight);
            test::compareKernelWithHost(*device, *shared / "cs123" / "scenes" / scene, settings,
                                        std::string("optics_") + fs::path(scene).stem().string());
        }
    }
}

TEST_CASE("kernel matches host on area lights with few samples and stratified AA", "[kernel][kvh][optics]") {
    auto device = test::cpuDevice();
    if (!device) {
        test::skip("no OpenCL CPU device (install pocl-opencl-icd)");
        return;
    }
    // Few area samples and one camera sample a pixel: any difference in the sample
    // pattern between the renderers would show as noise that does not match.
    RenderSettings settings = test::settingsFromOptions("--aa stratified --samples 1 --seed 3", 96, 72);
    settings.areaSamples = 4;
    test::compareKernelWithHost(*device, test::scenesDir() / "light_area.xml", settings, "area_4_samples");
}
