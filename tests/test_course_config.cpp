// The course's .ini configs (app/course_config.h) and `ray CONFIG.ini` on the command line.
#include <catch2/catch.hpp>

#include <fstream>
#include <string>

#include "app/cli.h"
#include "app/course_config.h"
#include "scene/scene.h"
#include "test_support.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using ray::AntialiasMode;
using ray::CourseConfig;
using ray::RenderSettings;
using ray::TextureFilter;

namespace {

// The course's spot_light_1.ini, as its template writes it.
const char* const kCourseConfig = R"([IO]
    scene = scenefiles/illuminate/required/spot_light/spot_light_1.json
    output = student_outputs/illuminate/required/spot_light_1.png

[Canvas]
    width = 1024
    height = 768

[Feature]
    shadows = true
    reflect = true
    refract = false
    texture = true
    parallel = false
    super-sample = false
    post-process = false
    acceleration = false
    depthoffield = false

[Settings]
    maximum-recursive-depth = 4
    samples-per-pixel = 1
)";

CourseConfig read(const std::string& text, bool strict = false) {
    return ray::readCourseConfig(text, "c.ini", RenderSettings{}, strict);
}

std::string errorOf(const std::string& text, bool strict = false) {
    try {
        read(text, strict);
    } catch (const ray::InputError& e) {
        return e.what();
    }
    return "";
}

// A minimal config with `extra` lines under [Feature].
std::string withFeatures(const std::string& extra) {
    return "[IO]\nscene = s.json\noutput = out/s.png\n[Feature]\n" + extra + "\n";
}

}  // namespace

TEST_CASE("a course config sets what the course's program reads from it", "[config]") {
    const CourseConfig config = read(kCourseConfig);
    CHECK(config.scene == "scenefiles/illuminate/required/spot_light/spot_light_1.json");
    CHECK(config.output == "student_outputs/illuminate/required/spot_light_1.png");
    const RenderSettings& s = config.settings;
    CHECK(s.width == 1024);
    CHECK(s.height == 768);
    CHECK(s.shadows);
    CHECK(s.reflections);
    CHECK_FALSE(s.refraction);
    CHECK(s.textures);
    CHECK_FALSE(s.depthOfField);  // ray's default is on: the config turns it off
    CHECK(s.antialias == AntialiasMode::Off);  // no super-sampling: one ray through the centre
    CHECK(s.maxDepth == 4);
    CHECK(config.warnings.empty());
}

TEST_CASE("a course config's left-out switches are off and its depth 0, as the course reads them", "[config]") {
    const RenderSettings s = read("[IO]\nscene = s.json\n").settings;
    CHECK_FALSE(s.shadows);
    CHECK_FALSE(s.reflections);
    CHECK_FALSE(s.textures);
    CHECK(s.maxDepth == 0);
    CHECK(s.width == RenderSettings{}.width);
}

TEST_CASE("a course config's super-sampling and texture filter map onto ray's", "[config]") {
    const std::string supersampled = "[IO]\nscene = s.json\n[Feature]\nsuper-sample = true\n[Settings]\n";
    RenderSettings s = read(supersampled + "samples-per-pixel = 9\nsuper-sampler-pattern = \"grid\"\n").settings;
    CHECK(s.antialias == AntialiasMode::Stratified);
    CHECK(s.samples == 9);
    CHECK(read(supersampled + "super-sampler-pattern = \"adaptive\"\n").settings.antialias == AntialiasMode::Adaptive);
    CHECK(read(withFeatures("texture-filter = \"bilinear\"")).settings.textureFilter == TextureFilter::Bilinear);
    CHECK(read(withFeatures("texture-filter = \"bilinear\"\nmipmapping = true")).settings.textureFilter ==
          TextureFilter::Trilinear);
    CHECK(read(withFeatures("texture-filter = nearest")).settings.textureFilter == TextureFilter::Nearest);
    CHECK_THAT(errorOf(withFeatures("texture-filter = \"trilinear\"")),
               Contains("c.ini:5: error: trilinear filtering needs mip-mapping"));
}

TEST_CASE("a course config's unknown key warns, naming it, a malformed value is an error", "[config]") {
    const CourseConfig config =
        read("[IO]\nscene = s.json\n[Feature]\nshadow = true\nsamples-per-pixel = 4\npost-process = true\n");
    REQUIRE(config.warnings.size() == 3);
    CHECK(config.warnings[0] == "c.ini:4: warning: unknown key 'shadow' in [Feature]; it is ignored");
    CHECK_THAT(config.warnings[1], Contains("unknown key 'samples-per-pixel' in [Feature] (the course's program reads "
                                            "it in [Settings]); it is ignored"));
    CHECK_THAT(config.warnings[2], Contains("ray has no post-processing"));
    CHECK_THAT(errorOf("[IO]\nscene = s.json\n[Feature]\nshadow = true\n", true),
               StartsWith("c.ini:4: error: unknown key 'shadow'"));
    CHECK_THAT(errorOf(withFeatures("shadows = yes")), Contains("c.ini:5: error: shadows must be true or false, not 'yes'"));
    CHECK_THAT(errorOf("[IO]\nscene = s.json\n[Canvas]\nwidth = big\n"),
               Contains("c.ini:4: error: width must be a whole number, not 'big'"));
    CHECK_THAT(errorOf("[IO]\nscene = s.json\n[Canvas]\nwidth = 0\n"), Contains("width must be between 1 and 16384"));
    CHECK_THAT(errorOf("[IO]\nscene = s.json\n[Settings]\nmaximum-recursive-depth = -1\n"),
               Contains("maximum-recursive-depth must be between 0 and 64"));
    CHECK_THAT(errorOf("[IO]\noutput = x.png\n"), Contains("c.ini: error: the config names no scene"));
    CHECK_THAT(errorOf("[IO\nscene = s.json\n"), Contains("c.ini:1: error: a section line without its ']'"));
    CHECK_THAT(errorOf("[IO]\nscene s.json\n"), Contains("c.ini:2: error: 'scene s.json' is neither"));
    CHECK_THAT(errorOf(withFeatures("texture-filter = \"cubic\"")), Contains("texture-filter must be"));
}

TEST_CASE("ray CONFIG.ini takes the config, and what follows it overrides it", "[config][cli]") {
    const fs::path file = ray::test::outputDir() / "course_config_cli.ini";
    std::ofstream(file) << kCourseConfig;
    ray::CliOptions options = ray::parseCommandLine({file.string()});
    CHECK(options.config == file);
    CHECK(options.scene == "scenefiles/illuminate/required/spot_light/spot_light_1.json");
    CHECK(options.output == "student_outputs/illuminate/required/spot_light_1.png");
    CHECK(options.configOutput == options.output);
    CHECK_FALSE(options.settings.depthOfField);
    CHECK(options.settings.antialias == AntialiasMode::Off);

    options = ray::parseCommandLine({file.string(), "320", "240", "2", "--aa", "course", "-o", "x.png", "--no-shadows"});
    CHECK(options.settings.width == 320);
    CHECK(options.settings.height == 240);
    CHECK(options.settings.maxDepth == 2);
    CHECK(options.settings.antialias == AntialiasMode::Course);
    CHECK_FALSE(options.settings.shadows);
    CHECK(options.output == "x.png");
    CHECK_FALSE(options.settings.refraction);  // still the config's

    std::ofstream(file) << "[IO]\nscene = s.json\n[Feature]\nshadow = true\n";
    CHECK(ray::parseCommandLine({file.string()}).configWarnings.size() == 1);
    CHECK_THROWS_WITH(ray::parseCommandLine({file.string(), "--strict"}), Contains("unknown key 'shadow'"));
    CHECK_THROWS_WITH(ray::parseCommandLine({(ray::test::outputDir() / "absent.ini").string()}),
                      Contains("absent.ini: error: cannot open the config"));
}

TEST_CASE("ray CONFIG.ini renders its scene into the folder the config names, made if missing", "[config][cli]") {
    const fs::path work = ray::test::outputDir() / "course_config_run";
    fs::remove_all(work);
    fs::create_directories(work / "scenefiles");
    std::ofstream(work / "scenefiles" / "s.json") << R"({
  "globalData": {"ambientCoeff": 0.5, "diffuseCoeff": 0.5, "specularCoeff": 0.5},
  "cameraData": {"position": [0, 0, 5], "up": [0, 1, 0], "heightAngle": 45, "look": [0, 0, -1]},
  "groups": [{"lights": [{"type": "directional", "color": [1, 1, 1], "direction": [0, 0, -1]}],
              "primitives": [{"type": "sphere", "diffuse": [1, 0, 0]}]}]
})";
    std::ofstream(work / "c.ini") << "[IO]\nscene = " << (work / "scenefiles" / "s.json").string()
                                  << "\noutput = " << (work / "outputs" / "deep" / "s.png").string()
                                  << "\n[Canvas]\nwidth = 32\nheight = 24\n[Feature]\nshadows = true\n";
    const ray::test::CommandResult result = ray::test::runRay({(work / "c.ini").string(), "--device", "ref"});
    INFO(result.output);
    CHECK(result.exitCode == 0);
    const ray::Image image = ray::readImage(work / "outputs" / "deep" / "s.png");
    CHECK(image.width == 32);
    CHECK(image.height == 24);

    std::ofstream(work / "bad.ini") << "[IO]\nscene = " << (work / "scenefiles" / "s.json").string()
                                    << "\n[Canvas]\nwidth = wide\n";
    const ray::test::CommandResult bad = ray::test::runRay({(work / "bad.ini").string()});
    CHECK(bad.exitCode == 2);
    CHECK_THAT(bad.output, Contains("bad.ini:4: error: width must be a whole number, not 'wide'"));
}
