// --fresnel (issue 13, SPEC §4): the exact Fresnel reflectance (host/reference/optics.h,
// cl/shading/optics.cl), the weights it puts on the branches of transparent surfaces in the
// reference renderer, and the kernel against the host with it on.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "app/cli.h"
#include "kernel_comparison.h"
#include "reference/optics.h"

namespace fs = std::filesystem;
using namespace ray;

namespace {

// R for a ray meeting the interface at `degrees` from its normal.
double reflectanceAt(double degrees, double n1, double n2) {
    return fresnelReflectance(std::cos(radians(degrees)), n1, n2);
}

fs::path slabScene() { return test::testDataDir() / "scenes" / "fresnel_slab.xml"; }

// The centre pixel of the 9×9 slab scene: the ray through it meets the slab head on.
Vec3 slabCentre(const std::string& options, int depth = 4) {
    Scene scene = test::loadSceneQuietly(slabScene());
    Image image = renderReference(scene, test::settingsFromOptions("--aa off " + options, 9, 9, depth));
    return image.at(4, 4);
}

}  // namespace

TEST_CASE("Fresnel reflectance: head on, ((n1 - n2)/(n1 + n2))^2 either way", "[reference][optics][fresnel]") {
    CHECK(fresnelReflectance(1, 1, 1.5) == Approx(0.04));
    CHECK(fresnelReflectance(1, 1.5, 1) == Approx(0.04));
    CHECK(fresnelReflectance(1, 1, 1.33) == Approx(std::pow(0.33 / 2.33, 2)));
    CHECK(fresnelReflectance(1, 1.33, 1.5) == Approx(std::pow(0.17 / 2.83, 2)));
    CHECK(fresnelReflectance(0.3, 1.5, 1.5) == 0);  // no interface, nothing reflected
}

TEST_CASE("Fresnel reflectance: known values at oblique incidence", "[reference][optics][fresnel]") {
    // Glass (n = 1.5) from air at 45°: R_s = 0.0920, R_p = 0.0085, their mean 0.0502.
    CHECK(reflectanceAt(45, 1, 1.5) == Approx(0.0502399).epsilon(1e-5));
    CHECK(reflectanceAt(60, 1, 1.5) == Approx(0.0891867).epsilon(1e-5));
    // At Brewster's angle (tan θ = n2/n1) the p wave is not reflected at all: R = R_s / 2,
    // R_s = ((n2² − n1²)/(n2² + n1²))² there.
    double brewster = std::atan(1.5);
    double rs = std::pow((1.5 * 1.5 - 1) / (1.5 * 1.5 + 1), 2);
    CHECK(fresnelReflectance(std::cos(brewster), 1, 1.5) == Approx(rs / 2).epsilon(1e-6));
    // Leaving glass into air at 30°, below the critical angle of 41.8°.
    CHECK(reflectanceAt(30, 1.5, 1) == Approx(0.0551902).epsilon(1e-5));
}

TEST_CASE("Fresnel reflectance: the same either way through the interface", "[reference][optics][fresnel]") {
    // A ray and its refracted ray see the same R (Stokes relations): R(n1→n2, θi) = R(n2→n1, θt).
    for (double degrees : {0.0, 10.0, 30.0, 45.0, 60.0, 80.0, 89.0}) {
        double sinT = std::sin(radians(degrees)) / 1.5;
        double cosT = std::sqrt(1 - sinT * sinT);
        INFO(degrees << "°");
        CHECK(reflectanceAt(degrees, 1, 1.5) == Approx(fresnelReflectance(cosT, 1.5, 1)).epsilon(1e-6));
    }
}

TEST_CASE("Fresnel reflectance: 1 at grazing incidence and under total internal reflection",
          "[reference][optics][fresnel]") {
    CHECK(fresnelReflectance(0, 1, 1.5) == 1);
    CHECK(fresnelReflectance(1e-7, 1, 1.5) > 0.9999);
    CHECK(reflectanceAt(89, 1, 1.5) > 0.8);
    // It grows with the angle of incidence from outside.
    double previous = 0;
    for (double degrees = 0; degrees < 90; degrees += 5) {
        double r = reflectanceAt(degrees, 1, 1.5);
        CHECK(r >= previous);
        previous = r;
    }
    // From inside: 1 beyond the critical angle, exactly where refractDirection finds no
    // refracted ray, and rising to 1 just before it.
    double critical = std::asin(1 / 1.5);
    Vec3 n{0, 1, 0}, t;
    for (double offset : {-1e-3, -1e-6, 1e-6, 1e-3, 0.3}) {
        double angle = critical + offset;
        Vec3 d{std::sin(angle), -std::cos(angle), 0};
        double r = fresnelReflectance(-dot(d, n), 1.5, 1);
        INFO("critical angle + " << offset);
        CHECK((r == 1) == !refractDirection(d, n, 1.5, 1, t));
    }
    CHECK(fresnelReflectance(std::cos(critical - 1e-6), 1.5, 1) > 0.99);
    CHECK(reflectanceAt(60, 1.5, 1) == 1);
    // A shading normal tilted past the ray (bump maps) counts by its magnitude.
    CHECK(fresnelReflectance(-0.5, 1, 1.5) == fresnelReflectance(0.5, 1, 1.5));
    // An ior of 0 or below (the loader takes any number) gives 1, never NaN.
    CHECK(fresnelReflectance(0.5, 1, 0) == 1);
    CHECK(fresnelReflectance(0.5, 1, -1) == 1);
}

TEST_CASE("the option --fresnel parses and is off by default", "[cli][fresnel]") {
    CHECK_FALSE(parseCommandLine({"a.xml"}).settings.fresnel);
    CHECK(parseCommandLine({"a.xml", "--fresnel"}).settings.fresnel);
    CHECK(std::string(kUsageText).find("--fresnel") != std::string::npos);
}

// The slab scene's centre pixel, worked by hand (R = 0.04 head on, the wall white, the
// slab reflective nowhere and lit by nothing):
//  - without --fresnel: kt·Ot = 1 on entry, weight 1 on the way out: 1;
//  - with it: 0.96 into the slab; at the back face 0.96 out to the wall and 0.04 kept
//    inside, back to the front face, where 0.96 leaves towards the camera (black) and 0.04
//    is reflected again, a path weight of 0.96·0.04·0.04 = 0.0015, below --threshold's
//    1/256: 0.96·0.96 = 0.9216;
//  - with --threshold 0 that branch goes on (depth 4: it reaches the back face at depth 3,
//    whose 0.96 reaches the wall): 0.9216 + 0.96·0.04·0.04·0.96 = 0.92307456.
TEST_CASE("Fresnel weighting (--fresnel) splits the light at both faces of a slab, inner reflections kept inside",
          "[reference][fresnel]") {
    CHECK(slabCentre("").x == Approx(1.0));
    CHECK(slabCentre("--fresnel").x == Approx(0.9216).epsilon(1e-6));
    CHECK(slabCentre("--fresnel --threshold 0").x == Approx(0.92307456).epsilon(1e-6));
    // The inner reflection belongs to refraction: --no-reflections keeps it.
    CHECK(slabCentre("--fresnel --threshold 0 --no-reflections").x == Approx(0.92307456).epsilon(1e-6));
    // Depth 3: the second inner reflection (children at depth 4) is not traced.
    CHECK(slabCentre("--fresnel --threshold 0", 3).x == Approx(0.9216).epsilon(1e-6));
    // --no-refraction renders the slab opaque, and --fresnel changes nothing then.
    CHECK(slabCentre("--fresnel --no-refraction").x == slabCentre("--no-refraction").x);
}

TEST_CASE("Fresnel weighting (--fresnel) changes transparent scenes and nothing else", "[reference][fresnel]") {
    auto render = [](const char* scene, const std::string& options) {
        return renderReference(test::loadSceneQuietly(test::scenesDir() / scene),
                               test::settingsFromOptions("--aa off " + options, 64, 48));
    };
    Image plain = render("refraction.xml", "");
    Image fresnel = render("refraction.xml", "--fresnel");
    test::ImageDifference d = test::compare8bit(fresnel, plain, 0);
    std::printf("refraction.xml --fresnel: %.1f%% of pixels unchanged, mean difference %.2f/255\n",
                d.fractionWithin * 100, d.meanAbsError);
    CHECK(d.fractionWithin < 0.9);
    CHECK(d.fractionWithin > 0.2);  // the walls and the floor seen directly stay as they were

    RenderSettings off = test::settingsFromOptions("--aa off", 64, 48);
    off.fresnel = false;
    CHECK(render("refraction.xml", "").rgb == renderReference(test::loadSceneQuietly(test::scenesDir() / "refraction.xml"), off).rgb);
    // No transparent material: not a bit changes.
    CHECK(render("primitives_all.xml", "--fresnel").rgb == render("primitives_all.xml", "").rgb);
    CHECK(render("reflection_depth.xml", "--fresnel").rgb == render("reflection_depth.xml", "").rgb);
}

TEST_CASE("kernel: --fresnel changes transparent scenes and nothing else", "[kernel][fresnel]") {
    auto device = test::cpuDevice();
    if (!device) {
        test::skip("no OpenCL CPU device (install pocl-opencl-icd)");
        return;
    }
    auto render = [&](const char* scene, const std::string& options) {
        return renderOpenCl(*device, test::loadSceneQuietly(test::scenesDir() / scene),
                            test::settingsFromOptions("--aa off " + options, 64, 48), {}, nullptr);
    };
    CHECK(test::compare8bit(render("refraction.xml", "--fresnel"), render("refraction.xml", ""), 0).fractionWithin < 0.9);
    CHECK(render("primitives_all.xml", "--fresnel").rgb == render("primitives_all.xml", "").rgb);
}

// The kernel's float against the host's double with --fresnel, held to the bounds of every
// kernel-versus-host test (kernel_comparison.h): every transparent bundled scene, the
// slab, and the course's refraction scenes.
TEST_CASE("kernel matches host with --fresnel", "[kernel][kvh][fresnel]") {
    auto device = test::cpuDevice();
    if (!device) {
        test::skip("no OpenCL CPU device (install pocl-opencl-icd)");
        return;
    }
    RenderSettings settings = test::settingsFromOptions("--fresnel", 160, 120);
    for (const char* scene : {"refraction.xml", "csg_lens.xml", "csg_nested.xml", "csg_die.xml", "csg_union.xml",
                              "csg_intersection.xml", "csg_difference.xml", "showpiece.xml"}) {
        SECTION(scene) {
            test::compareKernelWithHost(*device, test::scenesDir() / scene, settings,
                                        std::string("fresnel_") + fs::path(scene).stem().string());
        }
    }
    SECTION("fresnel_slab.xml") {
        test::compareKernelWithHost(*device, slabScene(), test::settingsFromOptions("--fresnel --threshold 0", 48, 48),
                                    "fresnel_slab");
    }
    SECTION("bumped_glass.xml") {
        test::compareKernelWithHost(*device, test::testDataDir() / "scenes" / "bumped_glass.xml", settings,
                                    "fresnel_bumped_glass");
    }
    auto shared = test::sharedDir();
    if (!shared) {
        test::skip("../shared/cs123 is absent: no course refraction scenes");
        return;
    }
    for (const char* scene : {"refract.xml", "refract2.xml", "refract_box.xml", "refract_whitted.xml", "ayidi_refract.xml"}) {
        SECTION(scene) {
            test::compareKernelWithHost(*device, *shared / "cs123" / "scenes" / scene,
                                        test::settingsFromOptions("--fresnel", 96, 72),
                                        std::string("fresnel_course_") + fs::path(scene).stem().string());
        }
    }
}
