// The reference renderer against the course's own renders (../shared/cs123/reference/):
// every scene of INDEX.tsv, rendered with the settings its ray_options column names, must
// match the course's png to within 8 levels on 99.5% of the pixels.
#include <catch2/catch.hpp>

#include <cstdio>
#include <string>

#include "image/image.h"
#include "reference/reference_renderer.h"
#include "scene/scene_loader.h"
#include "test_support.h"

TEST_CASE("the reference renderer matches the course's renders", "[conformance]") {
    auto shared = ray::test::sharedDir();
    if (!shared) {
        ray::test::skip("../shared/cs123 is absent: no course renders to compare with");
        return;
    }
    const std::filesystem::path course = *shared / "cs123";
    const auto cases = ray::test::readReferenceIndex(course / "reference" / "INDEX.tsv");
    REQUIRE(cases.size() == 18);

    ray::LoadOptions loadOptions;
    loadOptions.warn = [](const std::string&) {};  // the course files warn about little things
    for (const ray::test::ReferenceCase& c : cases) {
        INFO(c.image << " (" << c.scene << ", " << c.options << ")");
        ray::Scene scene = ray::loadScene(course / c.scene, loadOptions);
        ray::Image ours = ray::renderReference(scene, ray::test::settingsFromOptions(c.options, 1024, 768));
        ray::Image theirs = ray::readImage(course / "reference" / c.image);
        ray::test::ImageDifference d = ray::test::compare8bit(ours, theirs, 8);

        std::printf("%-40s within 8: %7.3f%%  mean abs error: %.4f  max: %3d\n", c.image.c_str(),
                    100 * d.fractionWithin, d.meanAbsError, d.maxError);
        const bool matches = d.fractionWithin >= 0.995 && d.meanAbsError <= 1.0;
        if (!matches) {
            auto stem = std::filesystem::path(c.image).stem().string();
            auto oursFile = ray::test::outputDir() / (stem + ".ours.png");
            auto differenceFile = ray::test::outputDir() / (stem + ".difference.png");
            ray::writeImage(ours, oursFile);
            ray::writeImage(ray::test::differenceImage(ours, theirs), differenceFile);
            std::printf("    wrote %s and %s\n", oursFile.c_str(), differenceFile.c_str());
        }
        std::fflush(stdout);
        CHECK(d.fractionWithin >= 0.995);
        CHECK(d.meanAbsError <= 1.0);
    }
}
